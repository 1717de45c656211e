// Orientation and packing of patches into atlas pages.
//
// Sources: each patch is turned to fit its minimal bounding rectangle, as in
// Sorkine & Cohen-Or, "Warped Textures for UV Mapping Encoding" (Eurographics
// 2001 short paper, section 4), found by rotating calipers on the convex hull
// (codec/core/geometry2d.h), then quantized to the format's rotation code. Packing goes
// beyond the paper (it left compact packing as future work): the patches' true
// shapes, rasterised conservatively and dilated by half the gutter, go to the
// lowest free position on an occupancy bitmap of cells (bottom-left fill,
// Chazelle 1983; on raster masks as in xatlas' brute-force packer), so small
// patches fill the holes that large ones leave. PackMethod::skyline instead
// drops them onto a skyline of cell columns ("tetris" packing, Levy et al.,
// "Least Squares Conformal Maps", SIGGRAPH 2002, section 5). Both try four
// 90 degree turns and several page widths, keeping the smallest page.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"
#include "format/bitstream/uvmap.h"

namespace gltfwarp {

// One primitive of an atlas group: its decoded mesh, partition and the
// patch-local corner positions from layout_patches.
struct PackPrimitive {
  const TriMesh* mesh = nullptr;
  std::span<const uint32_t> patch_of_face;  // one per face
  uint32_t patch_count = 0;
  std::span<const double> corner_xy;  // 2 per corner (6 per face), model units
  // Optional: source texels per model unit of each face (triangle_texel_density).
  // With PackOptions::per_patch_scale, each patch's scale_step is the ratio of
  // its source density to the whole set's (RMS, area-weighted): the budget
  // texel_scale sets is redistributed to where the source had its detail.
  std::span<const double> face_density;
  // Optional, one per patch: scale steps added to each patch's step (after
  // the density rule), e.g. negative where the content is smooth enough to
  // keep its quality with fewer texels.
  std::span<const int32_t> scale_step_bias;
  std::span<const uint32_t> seeds;   // empty (lowest faces) or one per patch: copied to UvMap::seeds
  std::span<const uint8_t> methods;  // empty (all unfold) or one per patch: copied to UvMap::methods
  SolveParams solve;                 // copied to UvMap::solve
  // Texel reuse (codec/encode/partition/twin_partition.h): empty, or per
  // patch the patch (of this primitive) it is a congruent copy of, or -1;
  // and per corner of a copy's face the original's corner. A copy whose
  // layout matches its original's within PackOptions::max_reuse_residual is
  // not packed: its fine placement (format 1.3) lands it on the original's texels.
  std::span<const int32_t> reuse_of;
  std::span<const uint32_t> twin_corner;
  // Optional: the source's TEXCOORD_0, 2 per corner. With
  // PackOptions::orientation source_axes, each patch turns so that the
  // source image's axes run along the atlas's.
  std::span<const float> source_uv;
  // Optional: the size of the source image(s) every TEXCOORD_0 slot of the
  // primitive samples (all one size, no texture transform). With
  // PackOptions::align_texels, a patch whose source map is a similarity
  // lands on the source's texel grid (texel_alignment.h). 0: never.
  uint32_t align_width = 0, align_height = 0;
};

// The block that atlas sides are multiples of (SizeRounding::multiple_of_16)
// and that texel-exact patches line up with the source's (align_mip_block):
// one number, since a patch's MIP chain is the source's only at the levels
// where the atlas halves exactly.
constexpr uint32_t kMipExactBlock = 16;

enum class SizeRounding : uint8_t {
  // Width and height rounded up to a multiple of 16, so that MIP levels 0..4
  // halve exactly and every viewer builds the same chain (an odd side has no
  // one rule: a box generator drops its last texel and shifts the level's
  // content by up to half a texel, a linear blit resamples it). At the
  // former 4-texel rounding the sides went odd from level 2 or 3 (500, 1204,
  // 1940), and the benchmark's renders (box-filtered chains) of the Duck's,
  // the Fox's and the truck's default files read 1.3-2.3 dB lower at 256 px
  // for it, for at most 15 more empty rows and columns. Also a multiple of
  // 4: block compression friendly.
  multiple_of_16,
  power_of_two,  // width and height rounded up to powers of two
};

enum class PackMethod : uint8_t {
  bitmap,   // bottom-left fill of true shapes on a cell bitmap (holes get filled)
  skyline,  // drop true shapes onto a skyline (faster, leaves holes under overhangs)
};

// How each patch is turned before its 90-degree variants are tried.
enum class PatchOrientation : uint8_t {
  min_rectangle,  // the patch's minimum-area rectangle axis-aligned (the paper's rule)
  // The source image's axes along the atlas's (from PackPrimitive::source_uv;
  // the minimum rectangle where a patch has none). The warp then resamples
  // the source along its own rows and columns: its straight edges stay
  // straight and PNG's and JPEG's row and block predictors keep working.
  // Duck, CesiumMilkTruck and MultiUVTest came out 3-12% smaller at the same
  // or better surface PSNR, for rectangles up to ~1.4x larger.
  source_axes,
};

struct PackOptions {
  double texel_scale = 0;          // texels per model unit; must be > 0 (see auto_texel_scale)
  uint32_t gutter = 4;             // min empty texels between two patches (half of it at page edges)
  uint32_t max_atlas_size = 4096;  // max page width and height in texels
  uint32_t max_pages = 1;          // > 1: spill into more max-size pages before shrinking the scale
  SizeRounding rounding = SizeRounding::multiple_of_16;
  bool rotate_90 = true;  // also try 90, 180, 270 degree turns of each patch
  PatchOrientation orientation = PatchOrientation::source_axes;
  PackMethod method = PackMethod::bitmap;
  bool per_patch_scale = true;   // use PackPrimitive::face_density when given
  int32_t min_scale_step = -16;  // per-patch scale range, in format steps of 2^(1/4):
  int32_t max_scale_step = 12;   // 1/16 .. 8 times texel_scale
  // How a patch's density comes from its faces' face_density: the area-weighted
  // quantile density_quantile (0.5: the median; 0.9 costs Duck 25% more
  // bytes for no measurable gain), or with density_quantile <= 0 the RMS
  // (texel-count preserving) mean.
  double density_quantile = 0.5;
  // > 0: a patch's scale is texel_scale * (its density / density_reference),
  // so texel_scale / density_reference scales every patch alike. 0: relative
  // to the whole set's RMS density (the budget texel_scale sets is only
  // redistributed).
  double density_reference = 0;
  uint32_t multi_order_max_patches = 400;  // up to this many patches, also try 2 more orders
  // Stop a (width, order) trial once its pages so far imply a larger area
  // than a finished trial's: it cannot win, so the packing is the same
  // either way, and only the time differs (BM_PackPatches in
  // benchmarks/bench_warp.cpp; CesiumMilkTruck's packs over a whole
  // encode: 8.9 -> 6.6 s).
  bool stop_losing_trials = true;
  bool true_shapes = true;    // false: pack each patch's bounding rectangle (for comparison)
  uint32_t search_depth = 3;  // bitmap: search holes down to this many patch heights
                              // above the lowest skyline point (bounds the work)
  uint32_t cell = 0;          // packing raster cell in texels; 0 = auto (1..4 by atlas size)
  // Texel reuse: the largest distance, in texels at the asked texel_scale,
  // between a copy's corner and its original's corner once fitted. Beyond
  // it the copy is packed as a patch of its own.
  double max_reuse_residual = 0.25;
  // Texel-exact patches (texel_alignment.h, PackPrimitive::align_width): the
  // largest distance, in source texels, between a corner's source position
  // and the similarity's; and the least scale, against the source's
  // density, a patch must have been given to be aligned instead (an aligned
  // patch holds the source's density: never fewer texels than asked, at most
  // 1/min_align_density^2 more).
  bool align_texels = true;
  double max_align_residual = 0.02;
  double min_align_density = 0.9;
  // An aligned patch's whole-texel position lines its MIP blocks up with
  // the source's (mip_block_residue) up to blocks of this many texels (a
  // power of 2). 16: levels 1 to 4, the levels the sides' rounding
  // (multiple_of_16) halves exactly, so the patch's whole chain is the
  // source's. At 4 (levels 1 and 2) the bench's renders at 256 px read
  // VertexColorTest 43.9 dB and TextureTransformTest 45.9 dB, their level-3
  // pixels 27 and 26 dB; at 16, 50.9 and 47.6 dB, for 64 and 60 more bytes
  // (8: 51.1 and 43.9 dB). 1: off.
  uint32_t align_mip_block = kMipExactBlock;
  double shrink_factor = 0.92;  // texel scale factor per retry when a page would be too large
  uint32_t max_retries = 60;    // give up (status too_large) after this many shrinks
};

enum class PackStatus : uint8_t {
  ok = 0,
  bad_input,  // null mesh, size mismatch, patch id out of range, texel_scale <= 0
  too_large,  // could not fit even after max_retries shrinks
};
const char* to_string(PackStatus s);

struct PackReport {
  uint32_t atlas_width = 0, atlas_height = 0, page_count = 0;
  uint32_t patch_count = 0;  // over all primitives
  double texel_scale = 0;    // final scale (lower than asked if the atlas had to shrink)
  uint32_t shrink_retries = 0;
  uint32_t trials = 0, stopped_trials = 0;  // (width, order) trials of the last attempt; stopped early
  uint64_t atlas_texels = 0;                // width * height * pages
  uint64_t covered_texels = 0;              // texels whose centre lies in a placed triangle
  double fill = 0;                          // covered_texels / atlas_texels
  uint64_t overlap_texels = 0;              // texel centres covered by two different patches (must be 0)
  uint64_t outside_texels = 0;   // texel centres of placed triangles outside their page (must be 0)
  uint32_t reused_patches = 0;   // copies placed on their originals' texels (not packed)
  double reused_texels = 0;      // their area in atlas texels: what reuse saved
  uint32_t aligned_patches = 0;  // patches on their source's texel grid (texel_alignment.h)
  double seconds = 0;            // wall time of pack_atlas
};

struct PackResult {
  std::vector<UvMap> maps;  // one per primitive, in input order (tau left at its default)
  PackReport report;
};

PackStatus pack_atlas(std::span<const PackPrimitive> prims, const PackOptions& options, PackResult& result);

// texel = s * R(rotation) * p + (x, y) with s = texel_scale * patch_scale(step):
// per-corner texel-space positions (not divided by the page size) for one
// primitive, with the decoder's arithmetic (placement_texel, decode_uvs.h),
// so fine placements (format 1.3) too.
void placed_corner_texels(std::span<const double> corner_xy, const UvMap& map,
                          std::vector<double>& corner_texel);

// Counts, for the report, texel centres covered by triangles of two patches and
// outside their page, rasterising every triangle of every primitive.
void measure_atlas(std::span<const PackPrimitive> prims, std::span<const UvMap> maps, PackReport& report);

}  // namespace gltfwarp
