// The implicit UV map of one primitive: what our bitstream carries in place
// of TEXCOORD_0, and the pure functions that write it, read it and turn it
// back into per-corner UVs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/mesh.h"

namespace gltfwarp {

// Rigid placement of one patch in the atlas. The UV (in texels, x right,
// y down the image rows) of a patch-local point p is
//   texel = s * R(rotation) * p + (x, y),   s = texel_scale * patch_scale(scale_step)
// and uv = texel / (atlas_width, atlas_height). R and patch_scale are defined by
// the format (rotation_cos_sin, patch_scale) with exact, table-driven values.
struct PatchPlacement {
  uint32_t rotation = 0;   // rotation code, 0 <= rotation < kRotationSteps
  int32_t x = 0, y = 0;    // translation in texels
  uint32_t page = 0;       // atlas page (0 unless page_count > 1)
  int32_t scale_step = 0;  // per-patch scale code, 0 = texel_scale alone
};

struct UvMap {
  float tau = 1.3f;              // distortion bound the encoder used (informative)
  float texel_scale = 1.0f;      // texels per model unit
  uint32_t atlas_width = 0;      // page size in texels
  uint32_t atlas_height = 0;
  uint32_t page_count = 1;
  uint32_t patch_count = 0;
  std::vector<uint32_t> patch_of_face;     // one per face, patches ordered by lowest face
  std::vector<PatchPlacement> placements;  // one per patch
};

}  // namespace gltfwarp
