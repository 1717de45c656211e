// Encoder only: merges adjacent patches of a finished partition into patches
// laid out by the solve method (codec/core/layout_solve.h, format 1.2). The
// unfolding replay folds unions over where two growth fronts meet; a Tutte +
// ARAP solve of the same union is fold-free by construction of its start and
// often stays within tau, so the union can be one patch and its seam goes.
// Where two patches cannot merge, a face of one that pokes into the other
// (a notch) can often still move across, which shortens the seam: the
// compact partition straightens its unfold seams so (embed.cpp), and the
// same moves between solve patches took the mixed layout's interior seam
// edges (one run, --always-implicit) Duck 424 -> 404, Fox 135 -> 124,
// CesiumMilkTruck 599 -> 575, sample-bumpy-sphere 241 -> 233, with smaller
// PNG atlases on each.
//
// A merge or move is accepted only on the decoder's own output: solve_patch's
// positions must give every face a positive exact orientation, a distortion
// <= tau, a simple boundary whose enclosed area equals the faces' area (no
// overlap, no wrapped vertex), and a fill no worse than allowed.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "codec/core/layout_solve.h"
#include "codec/core/mesh.h"

namespace gltfwarp {

// The solve the encoder asks of the decoder (the stream stores it): ARAP on
// cotangent weights (format 1.4) with enough rounds and CG steps to converge
// on patches of a few thousand faces. Against 1.2's uniform weights and
// (64, 8, 16) steps, the mixed layout's interior seam edges went (one run,
// --always-implicit): Duck 479 -> 424, sample-sphere 223 -> 173,
// sample-bumpy-sphere 335 -> 241, sample-torus 469 -> 371, Fox 138 -> 135,
// CesiumMilkTruck 634 -> 599.
// More Tutte steps changed nothing; more rounds or steps little.
inline constexpr SolveParams kEncoderSolveParams{128, 32, 64, true};

struct SolveMergeOptions {
  double tau = 1.3;
  SolveParams params = kEncoderSolveParams;  // what the stream will store
  uint32_t max_faces = 4096;                 // no solved patch larger (bounds the decoder's work per patch)
  double budget = 2.0;                       // trial solves may cover this many x face count faces (plus 64k)
  int rounds = 8;                            // passes over adjacent patch pairs
  double min_fill = 0.55;                    // a union must keep area/min-rect >= min(this, both parts' fill)
  double max_solved_share = 1;  // at most this share of all faces in solved patches (decode time)
};

// Whether two face sets may share a patch at all (the encoder's density and
// chart rules).
using JoinRule = std::function<bool(std::span<const uint32_t>, std::span<const uint32_t>)>;

// Rounds of two passes: merges (most shared edges first), then seam moves
// (a notch or hole face of patch A, with two or three edges on patch B,
// moves to B as in embed.cpp's seam straightening, when both patches then
// solve within the rules; both become solve patches), until a round changes
// nothing. patches: face sets (any order inside; emptied when merged away);
// xy: 6 doubles per face, the positions of the current layout, overwritten
// for the faces of new solve patches; method: one LayoutMethod per entry of
// patches (resized, unfold for untouched entries). Returns the number of
// merges plus faces moved: 0 when every patch still unfolds.
size_t solve_merge(const TriMesh& mesh, std::span<const uint32_t> opposite_corner,
                   std::vector<std::vector<uint32_t>>& patches, std::vector<double>& xy,
                   std::vector<uint8_t>& method, const SolveMergeOptions& options, const JoinRule& can_join);

// The acceptance test above, for one face set (ascending) already laid out
// in xy (6 doubles per face id): true when every face is positively
// oriented, within tau, and the patch covers the plane once.
bool solved_patch_acceptable(const TriMesh& mesh, std::span<const uint32_t> faces, std::span<const double> xy,
                             double tau);

}  // namespace gltfwarp
