// What the group's images would cost with explicit UVs at the quality the
// atlas reaches: the yardstick of the encoder's own keep-or-fall-back choice
// (issue 16: a smaller file proves nothing unless it is as good).
//
// Each source image the atlas would replace is re-encoded with the atlas's
// own image coder. Where that coder is lossy (JPEG or WebP colour), its quality
// is searched for the smallest file whose surface PSNR (the source's UVs,
// the same points and filter as the atlas's check) reaches the atlas's; the
// source's own bytes cap it, or its lossless re-coding where that is
// smaller. Where it is lossless (PNG, normal maps), the source images count
// as they are, or as our PNG writer codes them where that is smaller
// (lossless_repacks).
#pragma once

#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "codec/core/error.h"
#include "codec/encode/group_atlas.h"

namespace gltfwarp {

// Under rate control, the sizes a source image kept with explicit UVs may be
// written at besides its own, as fractions of it: what the benchmark's
// baseline 2 tries (a user who accepts fewer texels), and what the atlas's
// density does for the implicit map.
inline constexpr double kDownscales[2] = {0.71, 0.5};
// How rate control writes such an image: at `scale` of its size, through
// the coder asked, or losslessly (png) where that is smaller.
struct SourceForm {
  double scale = 1.0;
  bool png = false;
};
using SourceForms = std::map<int, SourceForm>;  // image -> its form (absent: its size, the coder asked)

struct EqualQualityImages {
  size_t bytes = 0;              // the replaceable source images, at equal quality
  double psnr = 0;               // their worst surface PSNR (0: as they are, lossless)
  int quality = 0;               // the coder's quality found (0: none re-encoded)
  std::map<int, int> qualities;  // per re-encoded image, its quality found (quality: their largest)
  std::string mime;              // the lossy coder's mimeType, where one was searched
  SourceForms forms;             // per re-encoded image found smallest at fewer texels (try_downscales)
};

// The images among `images` that the group's atlas would code lossily (a
// JPEG or WebP colour slot), each with the first such slot and its coding.
using LossySources = std::map<int, std::pair<SlotSource, SlotCoding>>;
LossySources lossy_sources(const tinygltf::Model& model, const AtlasGroup& group,
                           const EncodeOptions& options, const std::set<int>& images);
// Every colour-slot image among `images`, lossy or lossless, the same way:
// under a target (--target-psnr, no --image-quality) each may be written at
// fewer texels, PNG ones too (equal_quality_images' try_downscales).
LossySources targeted_sources(const tinygltf::Model& model, const AtlasGroup& group,
                              const EncodeOptions& options, const std::set<int>& images);

// Source images re-coded without changing a pixel, where that is smaller:
// image -> its new bytes (lossless_repacks). A group that keeps explicit UVs
// writes them (write_lossless_repacks), and the equal-quality alternative
// counts them: a user keeping explicit UVs can have them too.
using LosslessRepacks = std::map<int, std::vector<uint8_t>>;

// A group that keeps explicit UVs, when the user asked for JPEG or WebP
// images (--image-format) or a quality (rate control), gets its lossy-coded
// source images in that coder at the quality asked or found, like an atlas
// would have: `lossy` from lossy_sources (or sources_at_target), each in its
// form in `forms` (rate control's choice). The caller decides that it
// applies: with --image-format keep or png and no target, the sources stay.
// Sets why.images_recoded_quality and explicit_image_mime.
// An image that the coder asked does not make smaller stays as it was
// (why.images_kept): smaller and lossless beats larger and lossy. An image
// that `repacks` holds is compared at those bytes, and leaves `repacks` when
// it is re-coded (write_lossless_repacks must not put it back).
Error recode_sources_as_asked(tinygltf::Model& model, const LossySources& lossy, const SourceForms& forms,
                              SourceImages& sources, LosslessRepacks& repacks, Fallback& why);

// The sources among `images` that re-code smaller to the same pixels:
//  - PNGs that `lossy` does not code lossily and that hold only pixels
//    (png_holds_only_pixels: no colour profile or text to lose), through
//    our PNG writer;
//  - every JPEG, lossy or not, with its coefficients and segments kept and
//    its Huffman tables optimised (recode_jpeg_losslessly).
// Each is decoded back and kept only where its pixels are exactly the same.
Error lossless_repacks(const tinygltf::Model& model, const std::set<int>& images, const LossySources& lossy,
                       SourceImages& sources, LosslessRepacks& out);
// Puts them in the model; why.images_repacked and the bytes before and after.
void write_lossless_repacks(tinygltf::Model& model, const LosslessRepacks& repacks, Fallback& why);

// Normal maps under --image-format jpeg or webp. The atlas codes them with
// the coder asked, at the quality asked (as a user running any texture
// compressor on the file would), but no colour a viewer shows measures
// them, so no quality search applies. With explicit UVs they go out the
// same way, where that is smaller than they are (losslessly repacked or as
// is); each such image leaves `repacks`. Without this, a fallback of a
// JPEG encode kept TwoSidedPlane's normal map as a PNG: 26.6 KB more than
// its implicit file or baseline 1 spends at JPEG q10. image -> new bytes.
struct NormalMapsAsAsked {
  std::map<int, std::vector<uint8_t>> bytes;
  std::string mime;
  int quality = 0;  // their largest
};
Error normal_maps_as_asked(const tinygltf::Model& model, const AtlasGroup& group,
                           const EncodeOptions& options, const std::set<int>& images,
                           const LossySources& lossy, SourceImages& sources, LosslessRepacks& repacks,
                           NormalMapsAsAsked& out);
// Puts them in the model; why.normal_maps_recoded and their quality.
void write_normal_maps_as_asked(tinygltf::Model& model, const NormalMapsAsAsked& normals, Fallback& why);

// target_psnr: the atlas's floor_psnr(). `images`: the source images the
// atlas would replace (replaceable_images' set); `lossy`: lossy_sources of
// them (the caller keeps it for recode_sources_as_asked). An image that
// `repacks` or `normals` holds counts at those bytes unless it is searched.
// try_downscales (a target): a searched image is also tried at each of
// kDownscales of its size (without alpha), through the coder and as PNG,
// and the smallest file that reaches the target wins (out.forms). A form
// with fewer texels must reach it at MIP levels 0..3 too, against the
// source's own chain (mip_quality.h): what a minifying viewer shows. `lossy`
// may then hold lossless (PNG) slots too (targeted_sources): those are
// tried at fewer texels only.
Error equal_quality_images(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                           const GroupAtlas& built, SourceImages& sources, const std::set<int>& images,
                           const LossySources& lossy, const LosslessRepacks& repacks,
                           const NormalMapsAsAsked& normals, double target_psnr, bool try_downscales,
                           EqualQualityImages& out);

}  // namespace gltfwarp
