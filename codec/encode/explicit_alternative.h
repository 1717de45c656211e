// What the group's images would cost with explicit UVs at the quality the
// atlas reaches: the yardstick of the encoder's own keep-or-fall-back choice
// (issue 16: a smaller file proves nothing unless it is as good).
//
// Each source image the atlas would replace is re-encoded with the atlas's
// own image coder. Where that coder is lossy (JPEG or WebP colour), its quality
// is searched for the smallest file whose surface PSNR (the source's UVs,
// the same points and filter as the atlas's check) reaches the atlas's; the
// source's own bytes cap it. Where it is lossless (PNG, normal maps), the
// source images count as they are: nothing smaller is as good.
#pragma once

#include <cstddef>
#include <map>
#include <set>
#include <string>

#include "codec/core/error.h"
#include "codec/encode/group_atlas.h"

namespace gltfwarp {

struct EqualQualityImages {
  size_t bytes = 0;       // the replaceable source images, at equal quality
  double psnr = 0;        // their worst surface PSNR (0: as they are, lossless)
  int quality = 0;        // the coder's quality found (0: none re-encoded)
  bool searched = false;  // a lossy image was re-encoded
  // The images the atlas would code lossily, with the quality it would use
  // (the user's) and the coder (mime): what keeping explicit UVs re-encodes
  // them with when the user asked for JPEG or WebP.
  std::map<int, int> lossy_quality;
  std::string mime;
};

// target_psnr: the atlas's floor_psnr(). `images`: the source images the
// atlas would replace (replaceable_source_bytes' set).
Error equal_quality_images(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                           const GroupAtlas& built, const EncodeOptions& options, SourceImages& sources,
                           const std::set<int>& images, double target_psnr, EqualQualityImages& out);

}  // namespace gltfwarp
