// Texture warping: resample every TEXCOORD_0 texture of an atlas group from
// the source UV map into the atlas pages of the rebuilt UV map.
//
// Source: the warp of Sorkine & Cohen-Or, "Warped Textures for UV Mapping
// Encoding" (Eurographics 2001 short paper, section 4): each atlas texel
// finds its triangle and barycentric coordinates in the new layout and reads
// the source texture at the same barycentric point of the old UVs. The read is
// a filtered lookup whose footprint is the map's Jacobian (OIIO TextureSystem,
// anisotropic EWA-style MIP filtering with derivatives, see Heckbert 1989).
// Gutters are filled by a nearest-covered-texel dilation (a sampled
// "push" of the patch border, as in the usual texture-atlas padding).
// Tangent-space normal maps are re-expressed in the new tangent frame
// (codec/decode/tangents.h).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "codec/encode/texture/texel_fit.h"

namespace gltfwarp {

// glTF sampler wrap modes (wrapS / wrapT).
enum class WrapMode : uint8_t { repeat, mirrored_repeat, clamp_to_edge };
// glTF enum value (10497, 33648, 33071) to WrapMode; anything else is repeat.
WrapMode wrap_from_gltf(int gl_enum);

// How a slot's texels are encoded, which decides how they are filtered.
enum class SlotEncoding : uint8_t {
  srgb,    // baseColorTexture, emissiveTexture, sheen/specular colour: RGB filtered
           // in linear light, alpha linear
  linear,  // metallicRoughness, occlusion, transmission, clearcoat, ...: as is
  normal,  // tangent-space normal map: linear, xyz re-expressed in the new frame
};

// One primitive of the atlas group, as the warp sees it. Corners as in codec/core/mesh.h.
struct WarpPrimitive {
  std::span<const float> source_uv;        // 2 per corner: the source TEXCOORD_0
  std::span<const float> atlas_uv;         // 2 per corner: the new TEXCOORD_0 (decode_uvs)
  std::span<const uint32_t> page_of_face;  // atlas page of each face; empty = page 0
  // SlotEncoding::normal only (see codec/decode/tangents.h for how to compute them):
  std::span<const float> normals;       // 3 per corner: the shading normal
  std::span<const float> old_tangents;  // 4 per corner: frame of the source UVs (xyz, w)
  std::span<const float> new_tangents;  // 4 per corner: frame of the new UVs (xyz, w)
  // Optional, one per face: its 3D area, the weight of its samples in the
  // least-squares fit (what a viewer's screen sees). Empty: its source-UV
  // area in source texels (what surface_error weighs).
  std::span<const float> face_area;
};

// What the texels beyond every patch's gutter hold.
enum class EmptyFill : uint8_t {
  mean,  // the mean covered colour: flat, nearly free in PNG
  // A pull-push fill (codec/encode/texture/atlas_fill.h): smooth continuations of the
  // nearby patches. For JPEG: no step at patch outlines to spend
  // coefficients on: smaller JPEG atlases at the same or higher PSNR
  // (benchmarks/results/jpeg85: the corpus with its PNGs turned into JPEG
  // q85). As PNG it costs more than the other two (the Fox: +27%).
  // Blocks of 16 and then 8 texels that are wholly empty are then made flat
  // (flatten_empty_blocks): no AC coefficients where nothing is sampled.
  pull_push,
  // Each texel within WarpOptions::nearest_reach of a patch copies its
  // nearest covered or gutter texel, and farther ones run along their row
  // (nearest_fill in codec/encode/texture/atlas_fill.h): the gutter's
  // dilation carried as far as the MIP levels in play reach, so none of
  // them blends a patch's border with a foreign colour, at about the bytes
  // of the flat mean. What the encoder writes as PNG.
  nearest,
};

struct WarpOptions {
  SlotEncoding encoding = SlotEncoding::srgb;
  WrapMode wrap_s = WrapMode::repeat;  // source sampler wrapS
  WrapMode wrap_t = WrapMode::repeat;  // source sampler wrapT
  // KHR_texture_transform of the source slot, baked: the UV the source is
  // sampled at is (m[0]*u + m[1]*v + m[2], m[3]*u + m[4]*v + m[5]).
  float uv_transform[6] = {1, 0, 0, 0, 1, 0};
  uint32_t page = 0;                       // which atlas page to produce
  uint32_t gutter = 4;                     // fill texels up to this many texels from a patch by dilation
  EmptyFill empty_fill = EmptyFill::mean;  // the texels beyond the gutters
  // EmptyFill::nearest: how far from a patch, in texels, the nearest copies
  // reach. 8 is MIP level 3's block, the deepest level that 1024-px views
  // of whole corpus models sample much (benchmarks/results: render_by_mip);
  // reaching 16 (level 4) cost the CesiumMilkTruck 2.7% more bytes for
  // +0.1 dB in its 256-px views.
  uint32_t nearest_reach = 8;
  float anisotropy = 16;  // max anisotropy of the filtered lookup
  bool bicubic =
      false;  // bicubic (OIIO: a smoothing B-spline) when magnifying; false: bilinear, what viewers show
  // Where the atlas does not minify the source (footprint <= 1 source texel),
  // interpolate the source with the Catmull-Rom cubic (OIIO's filter)
  // instead of the texture system's bilinear lookup: an interpolating kernel
  // that keeps edges sharp, so the viewer's own bilinear pass is the only
  // blur. Minified lookups stay with the texture system's MIP filtering.
  bool cubic_magnification = true;
  // Faces on the source's texel grid (codec/encode/atlas/texel_alignment.h:
  // one source texel per atlas texel, a quarter turn or a reflection,
  // centres on centres) copy the source's texels, and their gutters hold
  // the source's texels beside them. For lossless atlases: a lossy coder
  // spends more on the copied gutter than the smoothing dilation (MultiUVTest
  // as JPEG q70: +6% bytes, -0.2 dB).
  bool copy_exact_texels = true;
  // Least-squares texels (texel_fit.h): after the point samples, the texels
  // that patches' bilinear reconstruction reaches are solved for, so that
  // what a viewer's bilinear filter shows best matches the source's own
  // bilinear over the surface; the gutter is then filled from them. Colour
  // and linear slots whose source fits in memory (as cubic_magnification);
  // normal maps stay point-sampled (their target depends on the frames).
  // Off by default: see EncodeOptions::least_squares_texels.
  bool least_squares = false;
  TexelFitOptions fit;
  float fit_samples_per_texel = 4;  // surface samples per texel of the finer grid (atlas or source)
  int threads = 0;                  // worker threads; 0 = hardware concurrency
  int band_rows = 32;               // rows per work item (memory is O(width * band_rows))
  std::string temp_dir;             // where the filtered source is staged; empty = system temp
};

enum class WarpStatus : uint8_t {
  ok = 0,
  bad_input,      // size mismatches, empty source, atlas size 0, missing normal-map frames
  texture_error,  // OIIO could not stage or read the source (message in WarpReport::error)
};
const char* to_string(WarpStatus s);

struct WarpReport {
  uint64_t covered_texels = 0;  // texels touched by a triangle of the page
  uint64_t gutter_texels = 0;   // texels filled by dilation
  uint64_t empty_texels = 0;    // texels beyond the gutters (EmptyFill)
  uint64_t lookups = 0;         // filtered source lookups
  double seconds = 0;
  double texels_per_second = 0;  // (covered + gutter) / seconds
  // The least-squares fit, when it ran: its unknowns and samples, its
  // error in linear values before/after (gain_db), its share of seconds.
  TexelFitReport fit;
  double fit_seconds = 0;
  std::string error;
};

// Warps `source` (any channel count 1..4, uint8/uint16/float) into a page of
// atlas_width x atlas_height texels. `out` gets the source's channel count and
// uint8 (uint16 for deeper sources) texels.
//
// `staged`: the source as stage_source made it for these options, or null
// (the warp stages it itself).
struct StagedSource;
WarpStatus warp_texture(const OIIO::ImageBuf& source, std::span<const WarpPrimitive> prims,
                        uint32_t atlas_width, uint32_t atlas_height, const WarpOptions& options,
                        OIIO::ImageBuf& out, WarpReport* report = nullptr,
                        const StagedSource* staged = nullptr);

// The source as the warp reads it: a tiled, MIP-mapped file of its linear
// values for OIIO's texture system, and those values in memory for the
// cubic lookups and the fit. Staging a 4096² source takes seconds (sRGB
// decoding, MIP filtering, writing the file), and an atlas's pages and its
// density rounds warp the same source: they share one (the 1M-face sample
// staged its 4096² texture once per page, four times).
struct StagedSource {
  std::string path;           // the file, removed with this object
  std::vector<float> linear;  // width * height * channels, or empty (over 2^24 texels, or not needed)
  int width = 0, height = 0, channels = 0;
  SlotEncoding encoding = SlotEncoding::srgb;
  StagedSource() = default;
  StagedSource(const StagedSource&) = delete;
  StagedSource& operator=(const StagedSource&) = delete;
  ~StagedSource();
};

// Stages `source` as warp_texture would under `options` (its encoding,
// cubic_magnification and temp_dir). Null on failure, with
// the reason in `error`.
std::shared_ptr<const StagedSource> stage_source(const OIIO::ImageBuf& source, const WarpOptions& options,
                                                 std::string& error);

}  // namespace gltfwarp
