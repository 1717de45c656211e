// decode_uvs: the function every decoder runs, and that the encoder runs too
// to get the UVs it warps its textures with (DESIGN.md, "The rule that makes
// the format work"): bitstream + decoded mesh -> per-corner TEXCOORD_0.
//   read_uvmap (uvmap_codec.h) -> layout_patches (codec/core/layout.h) -> apply_placements.
// Pure functions over caller memory; nothing is allocated before the header
// is validated; every failure is a UvStatus. spec/README.md, "Decoding process".
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/layout.h"
#include "codec/core/mesh.h"
#include "format/bitstream/uvmap.h"

namespace gltfwarp {

// corner_uv receives 2 floats per corner (6 per face):
//   t  = s * R(rotation) * p + (x, y)      (texels, double; s = texel_scale * patch_scale(step))
//   uv = (float)(t.x / atlas_width), (float)(t.y / atlas_height)
// and for a fine placement (1.3) R = (cos_q, sin_q) / 2^15, (x, y) gains
// (x_frac, y_frac) / 256, and a mirrored patch has p.y negated first.
// with the exact operation order of spec/README.md. corner_xy holds 2 doubles
// per corner (layout_patches' output); map must be valid for it
// (bad_argument otherwise: sizes, patch ids, placements out of range).
UvStatus apply_placements(std::span<const double> corner_xy, const UvMap& map, std::vector<float>& corner_uv);

// The texel position t above (before the division by the atlas size) of one
// patch-local point under placement pl of map, with the same arithmetic: for
// encoders that measure footprints in texels.
void placement_texel(const UvMap& map, const PatchPlacement& pl, double px, double py, double& tx,
                     double& ty);
// Atlas texels per model unit under placement pl (a fine placement's
// |(cos_q, sin_q)| / 2^15 included).
double placement_scale(const UvMap& map, const PatchPlacement& pl);

// read_uvmap + layout_patches + apply_placements. On success corner_uv has
// 6 floats per face and, if map_out is given, *map_out the decoded map.
UvStatus decode_uvs(const TriMesh& mesh, std::span<const uint8_t> bytes, std::vector<float>& corner_uv,
                    UvMap* map_out = nullptr);

// The UvStatus for a LayoutStatus (ok -> ok).
UvStatus from_layout_status(LayoutStatus s);

}  // namespace gltfwarp
