// decode_uvs: bitstream -> per-corner UVs (spec/README.md, "Decoding process").
// Built with -ffp-contract=off and without fast-math (CMakeLists.txt) so the
// double expressions below round identically everywhere.
#include "format/decode_uvs.h"

#include "format/uvmap_codec.h"

namespace gltfwarp {

UvStatus from_layout_status(LayoutStatus s) {
  switch (s) {
    case LayoutStatus::ok: return UvStatus::ok;
    case LayoutStatus::bad_patch_id: return UvStatus::layout_bad_patch_id;
    case LayoutStatus::patch_order: return UvStatus::layout_patch_order;
    case LayoutStatus::unreachable_face: return UvStatus::layout_unreachable_face;
    case LayoutStatus::bad_mesh: return UvStatus::bad_mesh;
  }
  return UvStatus::bad_mesh;
}

UvStatus apply_placements(std::span<const double> corner_xy, const UvMap& map,
                          std::vector<float>& corner_uv) {
  const size_t nf = map.patch_of_face.size();
  if (corner_xy.size() != nf * 6 || map.placements.size() != map.patch_count ||
      map.atlas_width == 0 || map.atlas_height == 0)
    return UvStatus::bad_argument;
  for (const uint32_t p : map.patch_of_face)
    if (p >= map.patch_count) return UvStatus::bad_argument;
  const double w = static_cast<double>(map.atlas_width), h = static_cast<double>(map.atlas_height);
  corner_uv.resize(nf * 6);
  for (size_t f = 0; f < nf; ++f) {
    const PatchPlacement& pl = map.placements[map.patch_of_face[f]];
    double c, s;
    rotation_cos_sin(pl.rotation, c, s);
    const double scale = static_cast<double>(map.texel_scale) * patch_scale(pl.scale_step);
    const double sc = scale * c, ss = scale * s;
    const double tx0 = static_cast<double>(pl.x), ty0 = static_cast<double>(pl.y);
    for (size_t k = 0; k < 3; ++k) {
      const size_t corner = 3 * f + k;
      const double px = corner_xy[2 * corner], py = corner_xy[2 * corner + 1];
      const double tx = (sc * px - ss * py) + tx0;
      const double ty = (ss * px + sc * py) + ty0;
      corner_uv[2 * corner] = static_cast<float>(tx / w);
      corner_uv[2 * corner + 1] = static_cast<float>(ty / h);
    }
  }
  return UvStatus::ok;
}

UvStatus decode_uvs(const TriMesh& mesh, std::span<const uint8_t> bytes, std::vector<float>& corner_uv,
                    UvMap* map_out) {
  UvMap local;
  UvMap& map = map_out ? *map_out : local;
  if (const UvStatus s = read_uvmap(bytes, mesh, map); s != UvStatus::ok) return s;
  std::vector<double> corner_xy;
  if (const LayoutStatus ls = layout_patches(mesh, map.patch_of_face, map.patch_count, corner_xy);
      ls != LayoutStatus::ok)
    return from_layout_status(ls);
  return apply_placements(corner_xy, map, corner_uv);
}

}  // namespace gltfwarp
