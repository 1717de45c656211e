// The encoder: a glTF scene in, the same scene out with Draco geometry and,
// for every primitive whose material samples textures through TEXCOORD_0,
// the implicit UV map (our extension) plus warped atlas textures.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "codec/core/error.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/encode_report.h"
#include "format/gltf/draco_geometry.h"

namespace gltfwarp {

// EncodeOptions::quality_weight.
enum class QualityWeight : uint8_t { source_texel, surface_area };

struct EncodeOptions {
  DracoOptions draco;             // quantization bits (defaults of common tools)
  bool raw_geometry = false;      // --geometry raw: float accessors, no Draco
  bool implicit_uvs = true;       // replace TEXCOORD_0 (off: plain Draco for everything)
  double tau = 1.3;               // distortion bound of every triangle
  bool greedy_partition = false;  // the paper's plain greedy growth (baseline)
  // --layout mixed (the default): also merge patches laid out by solve
  // (format 1.4); false: --layout unfold, every patch replays (1.0/1.1).
  bool mixed_layout = true;
  bool report_greedy = false;  // also run greedy on each primitive and report its figures
  // Partition the parts of a cut primitive side by side, ahead of the loop
  // that commits them one by one (implicit_uv_encoder.cpp). Off: one after
  // another, the same bytes, slower; tests compare the two.
  bool prefetch_partitions = true;
  // Texel reuse (format 1.3): faces that show the same source texels through
  // congruent triangles (mirrored halves, repeats) get copy patches that land
  // on their originals' texels, so the atlas holds them once (twin_partition.h).
  bool texel_reuse = true;
  bool keep_source_charts = true;  // compact: no patch crosses a source UV seam (source_charts.h) ...
  bool cross_hidden_seams = true;  // ... unless the textures agree across it (seam_continuity.h)
  double texel_density = 0;        // texels per model unit; 0 = measured from the source (below)
  DensityMode texel_budget = DensityMode::preserve_texel_count;  // how "measured" counts source texels
  double texel_density_factor = 1.0;  // multiplies the measured density (e.g. 0.5 for half the detail)
  uint32_t max_atlas_size = 4096;     // largest atlas side in texels
  uint32_t max_pages =
      16;          // pages per atlas group before the density shrinks to fit (codec/encode/atlas/pages.h)
  int gutter = 4;  // texels of padding around every patch
  // Least-squares texels (codec/encode/texture/texel_fit.h): the atlas
  // texels whose bilinear reconstruction best matches the source over the
  // surface, instead of one point sample each. Opt-in: at equal surface
  // PSNR it costs bytes (Duck and CesiumMilkTruck, PNG and JPEG 50/75/90,
  // benchmarks/README.md): its sharper texels compress worse, an indexed PNG
  // snaps them back to the palette, and the adaptive density spends its
  // gain in fewer texels.
  bool least_squares_texels = false;
  bool power_of_two = false;     // atlas sides as powers of two (else multiples of 16)
  bool orient_to_source = true;  // --orientation source: patches turned to the source image's axes
  // Patches whose source map is a similarity land on the source's texel
  // grid and keep its texels exactly (texel_alignment.h); false: --resample-all.
  bool align_texels = true;
  // keep | png | jpeg | webp. WebP (lossy) is written only when asked: the
  // file then requires EXT_texture_webp, which not every viewer reads.
  std::string image_format = "keep";
  int image_quality = 0;  // JPEG/WebP quality, 1..100; 0 = the source JPEG's (90 for others)
  // Quality floor of every warped atlas (surface PSNR against the source,
  // dB, colour slots, of the texels the file will hold: after palette
  // snapping and JPEG coding; warp_quality.h). -1: 38 with the default auto
  // density, off when a density or factor was chosen; 0: off.
  // Below it, the density goes up by each of density_boosts in turn; still
  // below, the group keeps explicit UVs (unless quality_fallback is false).
  double min_psnr = -1;
  // What the floor, the goal and a target weigh each surface point by
  // (--quality-weight): every source texel alike (a face counts by its UV
  // area), or each face by its 3D area (by what a view of the whole
  // surface shows of it: a face with many texels on little surface, such
  // as a polar map's pole, counts by its surface).
  QualityWeight quality_weight = QualityWeight::source_texel;
  std::vector<double> density_boosts = {1.5, 2.0};
  bool quality_fallback = true;
  // With the floor on: give patches whose content is smooth half their
  // texels (two scale steps) while the group keeps the floor plus 0.5 dB.
  bool adaptive_density = true;
  // Halvings a patch may get (each round: two scale steps). Rounds stop early
  // once one no longer shrinks the images: smooth content (the Duck) keeps
  // shrinking over several rounds for a fraction of a dB, while models with
  // no headroom above the floor stop after the first (benchmarks/results/).
  int adaptive_rounds = 6;
  // Quality goal (dB) the density aims at. -1 (default): 44 dB, near
  // transparency, where the group's colour images are coded losslessly
  // (PNG): below it the density goes up by density_boosts, and texels are
  // never halved below it; if the atlas then outweighs the source images,
  // the group keeps explicit UVs (with a lossless coder the sources are the
  // better file). With a lossy coder (JPEG) the coder caps the quality, so
  // the goal is 40 dB and only bounds the halving while the atlas is no
  // larger than its sources. A positive value aims at that instead, boosting
  // and strict, with any coder. 0: trade quality for bytes down to min_psnr.
  double goal_psnr = -1;
  // Rate control packs and warps the layouts every coder quality starts
  // from once, and copies them for the next quality (group_atlas.h,
  // LayoutMemo). The file is the same either way; false is the baseline
  // the benchmark times it against (benchmarks/bench_rate_control.cpp).
  bool layout_memo = true;
  std::function<void(const std::string& stage, double fraction)> progress;  // may be empty
};

// Encodes `model` in place. On error the model may be half-written and
// must not be saved.
Error encode_model(tinygltf::Model& model, const EncodeOptions& options, EncodeReport& report);

}  // namespace gltfwarp
