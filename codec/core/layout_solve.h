// The second layout method (format 1.2, spec/README.md section 6.7): a patch laid
// out by a fixed-cost solve instead of the replay's unfolding. Encoder and
// decoder run this one function, like the replay (DESIGN.md, "The rule that
// makes the format work"); every iteration count is in SolveParams, which the
// stream stores, and no floating-point comparison decides anything.
//
// The method (normative; spec/README.md describes the same operations):
//  1. Validation: the patch must be a topological disc (layout.h's
//     LayoutStatus::not_disc otherwise): no face names a vertex twice; no
//     directed edge (a, b) appears in two faces; every vertex starts at most
//     one boundary edge (a directed edge whose reverse is in no face of the
//     patch); the boundary edges form a single loop of >= 3 edges;
//     2V - F - B == 2 (Euler characteristic 1, B boundary edges); every
//     vertex is connected to the loop by patch edges.
//  2. Boundary on a circle (Tutte's convex boundary): the loop starts at its
//     lowest vertex id and follows the faces' winding; each boundary vertex
//     goes to the angle 2 pi u of its cumulative 3D arc length fraction u,
//     through a rational (Pade) tangent and two angle doublings, so only
//     + - * / are used and the loop start lands at the origin.
//  3. Tutte embedding (Tutte 1963; Floater 2003 proves it fold-free for a
//     convex boundary): the interior vertices solve the uniform-weight
//     Laplacian system by `tutte_iterations` conjugate-gradient steps from 0.
//  4. As-rigid-as-possible refinement (Sorkine & Alexa 2007; Liu et al.,
//     "A Local/Global Approach to Mesh Parameterization", 2008):
//     `arap_iterations` rounds of a local step (each face's best rotation of
//     its isometric 2D copy, by the 2x2 closed form with one sqrt) and a
//     global step (`arap_cg_iterations` CG steps, the loop start pinned at
//     the origin, warm-started). The ARAP energy's edge weights are those of
//     the Tutte step (1 per face holding the edge), or, with
//     `cotangent_weights` (format 1.4), each face's cotangent of the angle
//     opposite the edge, clamped to [1/16384, 16]: the discrete ARAP energy
//     itself, which converges to lower stretch on irregular meshes.
//  5. A similarity scale: all positions times (sum of 3D edge lengths) /
//     (sum of 2D edge lengths), over the faces' edges.
// Divisions by a computed value that may be 0 add kSolveTiny to the divisor
// instead of branching (x / (d + tiny) == x / d for any d above ~1e-284).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/geometry2d.h"
#include "codec/core/mesh.h"

namespace gltfwarp {

struct SolveParams {
  uint32_t tutte_iterations = 64;    // CG steps of the Tutte system
  uint32_t arap_iterations = 8;      // local-global rounds
  uint32_t arap_cg_iterations = 16;  // CG steps of each global step
  bool cotangent_weights = false;    // ARAP weighted by clamped cotangents (format 1.4)
  friend bool operator==(const SolveParams&, const SolveParams&) = default;
};
// Stream limits (the decoder's cost is bounded by them): tutte and arap CG
// steps <= kMaxSolveCg, arap rounds <= kMaxSolveRounds.
inline constexpr uint32_t kMaxSolveCg = 1024;
inline constexpr uint32_t kMaxSolveRounds = 64;
inline constexpr double kSolveTiny = 1e-300;
// The cotangent weight's clamp (format 1.4). The lower bound only keeps an
// obtuse corner's weight positive, so the system stays positive definite; at
// 1/16 it cost seams (Duck 443 against 424 edges), so it is small. The upper
// bound keeps a sliver's near-zero angle from swamping its neighbours.
inline constexpr double kSolveMinCot = 1.0 / 16384.0;
inline constexpr double kSolveMaxCot = 16.0;

// Reused storage of solve_patch (one per thread).
struct SolveScratch {
  std::vector<uint32_t> local;  // vertex id -> local index (only patch vertices are written)
  std::vector<uint32_t> verts, out_off, out_to, nbr_off, nbr, bout, loop, queue;
  std::vector<uint8_t> fixed, seen;
  std::vector<double> weight, diag, x, y, bx, by, r, p, q, frame, rot, face_weight;
};

enum class SolveStatus : uint8_t { ok, not_disc };

// Lays out the patch made of `faces` (ascending face ids, valid indices) and
// writes the position of each of its vertices to pos[vertex id] (pos has one
// entry per mesh vertex; other entries are untouched).
SolveStatus solve_patch(const TriMesh& mesh, std::span<const uint32_t> faces, const SolveParams& params,
                        std::vector<Vec2>& pos, SolveScratch& scratch);

// The ARAP weight of a face's edge from its isometric copy's corner
// opposite it, ax, ay and bx, by being the two edges from that corner
// (cotangent_weights, step 4): cot clamped to [1/16384, 16], by comparisons
// that pass a NaN through unchanged, as the spec writes them.
double solve_cotangent_weight(double ax, double ay, double bx, double by);

// The boundary point of arc length fraction u in [0, 1) on the circle of
// radius r through the origin (step 2), exposed for tests.
Vec2 solve_circle_point(double u, double r);

}  // namespace gltfwarp
