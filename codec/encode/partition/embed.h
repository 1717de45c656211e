// The partition: cut the decoded mesh D into patches that the shared replay
// (codec/core/layout.h) lays flat with every triangle's distortion at most tau,
// no flipped triangle and no overlap inside a patch. Encoder only: every
// decision with a threshold lives here; the decoder sees membership alone.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/layout.h"
#include "codec/core/layout_report.h"
#include "codec/core/mesh.h"
#include "codec/encode/partition/solve_merge.h"

namespace gltfwarp {

enum class PartitionMode : uint8_t {
  compact,  // seeded balls sized to tau, merged, seams straightened (issue 8)
  greedy,   // the paper's plain BFS-rounds growth from the lowest free face (baseline)
};

struct EmbedOptions {
  double tau = 1.3;  // max distortion per triangle (paper's measure)
  PartitionMode mode = PartitionMode::compact;
  int place_attempts = 3;        // retries of a candidate after dropping its failing faces
  double normal_weight = 2.0;    // compact: ball cost factor (1 + w (1 - n.n_seed)) per unit length
  double ball_min_fill = 0.75;   // compact: shrink a ball (up to ball_shrinks times, by 1/4) while
  int ball_shrinks = 2;          //   its area / min-rect area is below this
  bool merge = true;             // compact: merge adjacent patches while the union still replays within tau
  double merge_budget = 3.0;     // compact: merge trials may regrow this many x face count faces
                                 //   (plus a fixed 256k, so small meshes get every trial)
  int merge_rounds = 8;          // compact: passes over adjacent patch pairs
  double merge_min_fill = 0.55;  // compact: a merge must keep area/min-rect >= this ...
  double merge_max_cone_deg = 160.0;  // compact: skip merge trials whose normals spread wider
  uint32_t merge_small_faces = 12;    // ... unless the smaller part has at most this many faces
  int straighten_rounds = 16;         // compact: passes moving notch and hole faces across seams
  double straighten_budget = 1.0;     // compact: their regrowth budget, x face count (plus 256k)
  double remerge_budget = 1.0;        // compact: the merge pass after straightening, x face count
  // Compact: source texel density per face (texels per model unit, from
  // triangle_texel_density; 0 or not finite = unknown). When given, no region
  // and no merge puts two faces of known density whose densities differ by
  // more than max_density_ratio into one patch, so the packer's per-patch
  // scale can give densely textured parts (eyes, labels) their own detail.
  // Balls skip, and seam straightening never moves, a face that would break it.
  // One exception: a hole (1-3 faces inside one other patch) whose faces
  // have less source detail than that patch joins it, since they only gain
  // texels there (stretched source UVs left the Duck with 4 such holes).
  std::span<const double> face_density;  // empty, or one per face
  // > 1; <= 1 or not finite disables the rule. A low ratio costs patches and
  // seams for no quality; a high one (or none) lets the Duck's eyes and body
  // share patches whose median density minifies the eyes, and its PSNR
  // falls (figures: scripts/bench, benchmarks/results/).
  double max_density_ratio = 8.0;
  // Compact: the source UV chart of each face (source_charts.h), or empty.
  // When given, no patch holds faces of two charts, so no patch crosses a
  // source UV seam (the viewer would blend two unrelated source regions
  // along it). The encoder then relaxes the density rule to 32x. Images
  // shrink at the quality floor (patches no longer blur decals and panel
  // edges, so the adaptive density halves more of them), for a few more
  // seams on some models (figures: benchmarks/results/results.md, images
  // and patches columns). A seam with one chart on both sides (a slit) is
  // a chart boundary only where source_charts split the chart at it (a
  // marked colour step, parts that stay large, and added seams not much
  // longer than the slits); elsewhere a patch may cross it.
  std::span<const uint32_t> face_chart;
  // Compact: after the partition, merge adjacent patches into patches laid
  // out by the solve method (format 1.2, solve_merge.h) where the decoder's
  // solve of the union is fold-free, within tau and overlap-free, and move
  // notch faces across seams where both patches then solve so. Off: every
  // patch unfolds and the stream stays 1.0/1.1, byte for byte as before.
  bool solve_merge = false;
  SolveParams solve = kEncoderSolveParams;  // the solve's iteration counts (stored in the stream)
  uint32_t solve_max_faces = 4096;          // no solved patch larger
  double solve_budget = 2.0;                // trial solves cover at most this x face count faces (plus 64k)
  double solve_max_share = 1.0;             // at most this share of faces in solved patches
};

struct Embedding {
  LayoutStatus status = LayoutStatus::ok;
  std::vector<uint32_t> patch_of_face;  // patches numbered by lowest face
  uint32_t patch_count = 0;
  // The face each patch grows from (format 1.1); empty when every patch
  // grows from its lowest face (greedy mode, and compact when that holds).
  std::vector<uint32_t> seeds;
  // Format 1.2: one LayoutMethod per patch, or empty when every patch unfolds.
  std::vector<uint8_t> methods;
  SolveParams solve;
  std::vector<double> corner_xy;   // from layout_patches (what the decoder computes)
  std::vector<double> encoder_xy;  // what the encoder's growth computed (test: == corner_xy)
  EmbedReport report;
};

// Requires valid indices (mesh_indices_valid); otherwise status = bad_mesh.
Embedding embed(const TriMesh& mesh, const EmbedOptions& options = {});

}  // namespace gltfwarp
