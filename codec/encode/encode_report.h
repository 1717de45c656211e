// What the encoder did, as data: per primitive, per atlas, and notes on
// what was passed through and why. Programs (tests, benchmarks) read the
// fields; the CLI renders them to text (apps/report_format.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "codec/core/layout.h"

namespace gltfwarp {

// How the encoder wrote a primitive.
enum class Handling {
  implicit_uv,         // TEXCOORD_0 replaced by our extension (raw_geometry: plain accessors, else Draco)
  draco,               // Draco geometry; any UVs stay explicit
  raw,                 // plain float accessors (--geometry raw); any UVs stay explicit
  raw_morph_targets,   // plain accessors: Draco cannot carry morph targets
  fallback,            // meant for implicit UVs, kept them explicit: PrimitiveReport::fallback says why
  pass_not_triangles,  // left as it came: points or lines (PrimitiveReport::mode)
  pass_no_triangles,   // left as it came: no triangles to write
  pass_unsupported,    // left as it came: Draco cannot carry an attribute (PrimitiveReport::detail)
};

// Why a primitive (or its whole atlas group) kept explicit UVs.
enum class FallbackReason {
  none,
  texcoord_not_vec2,         // TEXCOORD_0 is not a VEC2
  no_triangles,              // nothing to embed
  no_triangles_after_draco,  // Draco dropped every triangle as degenerate
  embedding_failed,          // the partition failed (Fallback::layout)
  below_quality_floor,       // the warped atlas stayed below --min-psnr at every density tried
  explicit_smaller,          // explicit UVs and the source images cost fewer bytes than the map and atlas
  texture_repeats,           // the UVs tile or repeat the texture: the atlas would store every repeat
  texcoord_out_of_range,     // a TEXCOORD_0 value lies beyond +-kMaxSourceUv
  draco_refused,             // Draco cannot carry the geometry (the explicit path then passes it through)
};

// The largest TEXCOORD_0 magnitude the encoder warps from. A float there
// still resolves 1/1024 of a unit (a texel of a 1024-texel texture), and
// times the largest image side (65536) it stays an int; no real tiling
// comes near it. Beyond it the primitive keeps its explicit UVs, even with
// --always-implicit: the warp could not place a texel.
constexpr float kMaxSourceUv = 16384;

struct Fallback {
  FallbackReason reason = FallbackReason::none;
  LayoutStatus layout = LayoutStatus::ok;  // embedding_failed: the partition's status
  // below_quality_floor: the worst source image's surface PSNR (dB), at this
  // density factor, against the floor; capped: --max-atlas-size held the density.
  // explicit_smaller: psnr is the atlas's.
  double psnr = 0, density_factor = 0, min_psnr = 0;
  bool capped = false;
  // explicit_smaller: geometry and images with explicit UVs at the atlas's
  // quality, against those with the implicit map (bytes); the source images'
  // surface PSNR and coder quality there (0: kept as they are, lossless),
  // the coder's mimeType (image/jpeg or image/webp; also the coder the
  // sources were recoded with, images_recoded_quality).
  size_t explicit_bytes = 0, implicit_bytes = 0;
  double explicit_psnr = 0;
  int explicit_image_quality = 0;
  std::string explicit_image_mime;
  // explicit_smaller or below_quality_floor with --image-format jpeg or webp:
  // the source images were written with that coder at this quality (0: left
  // as they were).
  int images_recoded_quality = 0;
  // ... except these, kept as they were: in that coder and quality
  // (kept_recoded_quality) they came out no smaller (kept_recoded_bytes
  // against kept_bytes), so the coder would only have lost quality.
  uint32_t images_kept = 0;
  size_t kept_bytes = 0, kept_recoded_bytes = 0;
  int kept_recoded_quality = 0;
  // Under rate control (a target, no coder quality): the qualities were
  // chosen to reach target_psnr (the target, or the atlas's quality where
  // that is higher: the file the comparison priced), and these images kept
  // as they were, since no quality of the coder reaches it in fewer bytes.
  double target_psnr = 0;
  uint32_t images_kept_for_target = 0;
  size_t kept_for_target_bytes = 0;
  // ... of the images written again, these at fewer texels (the smallest
  // file that reaches the target), some of them as PNG: the smallest scale
  // of their sides.
  uint32_t images_downscaled = 0, images_downscaled_png = 0;
  double images_scale = 0;
  // Source images written again losslessly, smaller and to the same pixels
  // (lossless_repacks: PNGs by our PNG writer, JPEGs with optimised Huffman
  // tables), with their bytes before and after.
  uint32_t images_repacked = 0;
  size_t repacked_bytes_before = 0, repacked_bytes_after = 0;
  // Normal maps written with the coder asked (explicit_image_mime) at this
  // quality, as the atlas would have (normal_maps_as_asked).
  uint32_t normal_maps_recoded = 0;
  int normal_maps_quality = 0;
  // texture_repeats: the source texels the faces cover, each use counted
  // (what the atlas would hold), and the texels of the images they sample.
  double texel_uses = 0, image_texels = 0;
  // texcoord_out_of_range: the largest |TEXCOORD_0| value.
  double max_source_uv = 0;
};

// The source's own UV layout on the embedding mesh, the yardstick of our
// seams (measure_source_charts).
struct SourceChartMeasures {
  // Faces joined across edges whose two faces carry the same UVs at both ends.
  uint32_t charts = 0;
  // Charts that are no disc on this mesh (a slit, a hole): a patch must be
  // one, so ours cut them; and their share of the surface's 3D area.
  uint32_t non_disc_charts = 0;
  double non_disc_area = 0;
  // Interior edges between two charts; and between two of the charts the
  // partition ran with (seams the texture shows, slits, page regions):
  // no patch crosses one, so each is a seam of ours too.
  uint32_t seam_edges = 0, bound_seam_edges = 0;
  // The share of the surface the charts stretch past the rule our patches
  // keep, each chart at its own scale (area_beyond_tau_at_own_scale).
  double area_beyond_tau = 0;
};

struct PrimitiveReport {
  int mesh = -1, primitive = -1;
  Handling handling = Handling::draco;
  bool raw_geometry = false;  // implicit_uv: the geometry is plain accessors, not Draco
  Fallback fallback;          // handling == fallback
  int mode = -1;              // pass_not_triangles: the glTF primitive mode
  std::string detail;         // pass_unsupported: Draco's own message, shown as it is
  size_t triangles = 0, vertices = 0;
  size_t geometry_bytes = 0;   // Draco bytes (or raw accessor bytes)
  size_t bitstream_bytes = 0;  // our UV bitstream
  uint32_t patches = 0;
  double max_distortion = 0, mean_distortion = 0;
  size_t seam_edges = 0;
  double rect_fill = 0;  // area-weighted patch area / min-area rectangle
  uint32_t holes = 0;    // patches of 1-3 faces enclosed by one other patch
  struct {               // EncodeOptions::report_greedy: the plain greedy partition's figures
    uint32_t patches = 0, seam_edges = 0, holes = 0;
    double rect_fill = 0;
  } greedy;
  SourceChartMeasures source;  // the source's own UV charts beside our patches (source_chart_measures.h)
  size_t unmatched_faces = 0;  // decoded faces not traced back to a source face
  int atlas = -1;              // index into EncodeReport::atlases
  uint32_t cut_parts = 0;      // > 1: the source primitive was cut into this many, one atlas page each
};

struct AtlasReport {
  std::vector<int> primitives_meshes;               // informative
  uint32_t width = 0, height = 0;                   // the first page's
  std::vector<std::array<uint32_t, 2>> page_sizes;  // every page's width and height (one image set each)
  double fill = 0;                                  // covered texels / atlas texels, over the pages
  size_t overlapping_texels = 0;
  // Texel reuse (format 1.3): copy patches placed on their originals'
  // texels, and the atlas texels they would have taken of their own.
  uint32_t reused_patches = 0;
  double reused_texels = 0;
  // Texel-exact patches (texel_alignment.h): on their source's texel grid.
  uint32_t aligned_patches = 0;
  size_t source_image_bytes = 0, atlas_image_bytes = 0;
  double density_factor = 1;  // times the measured texel density
  double psnr = 0;  // surface PSNR of the warped colour slots, the worst source image's (0: none measured)
  // What a minifying viewer shows (mip_quality.h), colour slots pooled:
  // the mean surface PSNR at MIP levels 0..3, and the worst region's (the
  // worst patches holding 1% of the surface) at each level.
  std::array<double, 4> mip_psnr{}, worst_psnr{};
  // The group's geometry, bitstreams and atlas images (bytes), against the
  // same geometry with explicit UVs and the replaced source images at the
  // atlas's quality (explicit_alternative.h): the source images re-encoded
  // with the same coder (explicit_image_mime at quality explicit_image_quality,
  // surface PSNR explicit_psnr), or as they are where the coder is lossless
  // (both 0).
  size_t file_bytes = 0, explicit_bytes = 0;
  double explicit_psnr = 0;
  int explicit_image_quality = 0;
  std::string explicit_image_mime;
  // Rate control (--target-psnr or --quality with a lossy coder and no
  // --image-quality; quality_search.h): the coder quality chosen (0: none
  // searched), the qualities probed at uniform densities and those run
  // through the whole density pipeline, and whether the chosen one reached the target.
  int image_quality = 0;
  int quality_probes = 0;
  int quality_trials = 0;
  bool quality_reached = false;
  bool quality_uniform = false;  // the chosen quality's atlas is its probe's uniform layout
  // ... or rate control wrote the atlas losslessly (PNG): it reached the
  // target in fewer bytes than the lossy search's best (that quality, those
  // image bytes).
  bool lossless_chosen = false;
  int lossy_quality_beaten = 0;
  size_t lossy_bytes_beaten = 0;
  double fit_gain_db = 0;  // least-squares texels: dB gained over point samples (linear light, colour slots)
  double fit_seconds = 0;  // time the fit took, over the images and pages
};

// What a note is about.
enum class NoteKind {
  image_not_decodable,    // `image` cannot be decoded (`detail`): its users keep explicit UVs
  image_ktx2,             // `image` is KTX2, which the warp cannot decode: its users keep explicit UVs
  texture_in_extension,   // `texture` names its image in extension `detail`: the warp cannot rewrite it
  texture_without_image,  // `texture` has no image
  morph_targets_raw,      // kept raw: Draco cannot carry morph targets
  cut_into_parts,         // cut into `parts` primitives (the others appended to its mesh) for atlas pages
  fallback,               // kept explicit UVs: `fallback` says why
  no_triangles,           // passed through: it has no triangles
  draco_unsupported,      // passed through: Draco cannot carry it (`detail`: Draco's message)
};

struct Note {
  NoteKind kind = NoteKind::fallback;
  int mesh = -1, primitive = -1;  // the primitive it is about (-1: none)
  int image = -1, texture = -1;
  uint32_t parts = 0;
  std::string detail;  // a lower layer's message or an extension's name, shown as it is
  Fallback fallback;
  bool about(int m, int p) const { return mesh == m && primitive == p; }
};

struct EncodeReport {
  std::vector<PrimitiveReport> primitives;
  std::vector<AtlasReport> atlases;
  std::vector<Note> notes;  // what was passed through and why
};

}  // namespace gltfwarp
