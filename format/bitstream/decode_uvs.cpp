// decode_uvs: bitstream -> per-corner UVs (spec/README.md, "Decoding process").
// Built with -ffp-contract=off and without fast-math (CMakeLists.txt) so the
// double expressions below round identically everywhere.
#include "format/bitstream/decode_uvs.h"

#include "format/bitstream/uvmap_codec.h"

namespace gltfwarp {

UvStatus from_layout_status(LayoutStatus s) {
  switch (s) {
    case LayoutStatus::ok:
      return UvStatus::ok;
    case LayoutStatus::bad_patch_id:
      return UvStatus::layout_bad_patch_id;
    case LayoutStatus::patch_order:
      return UvStatus::layout_patch_order;
    case LayoutStatus::unreachable_face:
      return UvStatus::layout_unreachable_face;
    case LayoutStatus::bad_mesh:
      return UvStatus::bad_mesh;
    case LayoutStatus::bad_seed:
      return UvStatus::layout_bad_seed;
    case LayoutStatus::bad_method:
      return UvStatus::layout_bad_method;
    case LayoutStatus::not_disc:
      return UvStatus::layout_not_disc;
  }
  return UvStatus::bad_mesh;
}

namespace {

// One patch's placement as the numbers every corner of it uses.
struct PatchTransform {
  double sc = 0, ss = 0, tx0 = 0, ty0 = 0;
  bool mirror = false;
};

PatchTransform patch_transform(const UvMap& map, const PatchPlacement& pl) {
  double c, s, x = static_cast<double>(pl.x), y = static_cast<double>(pl.y);
  if (pl.fine) {
    // 1.3: these four are exact (a power-of-two scaling; x <= 2^16 plus 8
    // fraction bits), so a fine placement that repeats a coarse one
    // (cos_q = 2^15, sin_q = 0, no fraction) gives the coarse one's bits.
    c = static_cast<double>(pl.cos_q) * 0x1p-15;
    s = static_cast<double>(pl.sin_q) * 0x1p-15;
    x += static_cast<double>(pl.x_frac) * 0x1p-8;
    y += static_cast<double>(pl.y_frac) * 0x1p-8;
  } else {
    rotation_cos_sin(pl.rotation, c, s);
  }
  const double scale = static_cast<double>(map.texel_scale) * patch_scale(pl.scale_step);
  return {scale * c, scale * s, x, y, pl.fine && pl.mirror};
}

}  // namespace

double placement_scale(const UvMap& map, const PatchPlacement& pl) {
  const PatchTransform t = patch_transform(map, pl);
  return std::hypot(t.sc, t.ss);
}

namespace {

// texel = s R p' + (x, y), p' = p or (for a mirrored fine patch) p with its
// y negated (exactly, sign of zero included).
inline void corner_texel(const PatchTransform& t, double px, double py, double& tx, double& ty) {
  if (t.mirror) py = -py;
  tx = (t.sc * px - t.ss * py) + t.tx0;
  ty = (t.ss * px + t.sc * py) + t.ty0;
}

// The texel divided by the atlas size, rounded once to float.
inline void place_corner(const PatchTransform& t, double w, double h, double px, double py, float* uv) {
  double tx, ty;
  corner_texel(t, px, py, tx, ty);
  uv[0] = static_cast<float>(tx / w);
  uv[1] = static_cast<float>(ty / h);
}

std::vector<PatchTransform> patch_transforms(const UvMap& map) {
  std::vector<PatchTransform> t(map.placements.size());
  for (size_t p = 0; p < t.size(); ++p) t[p] = patch_transform(map, map.placements[p]);
  return t;
}

struct UvSink {
  const PatchTransform* transforms;
  double w, h;
  float* corner_uv;
  static void emit(void* context, uint32_t patch, uint32_t face, const Vec2 xy[3]) {
    const UvSink& s = *static_cast<const UvSink*>(context);
    const PatchTransform& t = s.transforms[patch];
    for (size_t k = 0; k < 3; ++k)
      place_corner(t, s.w, s.h, xy[k].x, xy[k].y, s.corner_uv + 2 * (3 * size_t{face} + k));
  }
};

}  // namespace

void placement_texel(const UvMap& map, const PatchPlacement& pl, double px, double py, double& tx,
                     double& ty) {
  corner_texel(patch_transform(map, pl), px, py, tx, ty);
}

UvStatus apply_placements(std::span<const double> corner_xy, const UvMap& map,
                          std::vector<float>& corner_uv) {
  const size_t nf = map.patch_of_face.size();
  if (corner_xy.size() != nf * 6 || map.placements.size() != map.patch_count || map.atlas_width == 0 ||
      map.atlas_height == 0)
    return UvStatus::bad_argument;
  for (const uint32_t p : map.patch_of_face)
    if (p >= map.patch_count) return UvStatus::bad_argument;
  const double w = static_cast<double>(map.atlas_width), h = static_cast<double>(map.atlas_height);
  const std::vector<PatchTransform> transforms = patch_transforms(map);
  corner_uv.resize(nf * 6);
  for (size_t f = 0; f < nf; ++f) {
    const PatchTransform& t = transforms[map.patch_of_face[f]];
    for (size_t k = 0; k < 3; ++k) {
      const size_t corner = 3 * f + k;
      place_corner(t, w, h, corner_xy[2 * corner], corner_xy[2 * corner + 1], &corner_uv[2 * corner]);
    }
  }
  return UvStatus::ok;
}

UvStatus decode_uvs(const TriMesh& mesh, std::span<const uint8_t> bytes, std::vector<float>& corner_uv,
                    UvMap* map_out) {
  UvMap local;
  UvMap& map = map_out ? *map_out : local;
  if (const UvStatus s = read_uvmap(bytes, mesh, map); s != UvStatus::ok) return s;
  // read_uvmap guarantees one placement per patch and a non-empty atlas; the
  // replay writes every corner of every face (each face is in one patch).
  const std::vector<PatchTransform> transforms = patch_transforms(map);
  corner_uv.resize(size_t{mesh.face_count()} * 6);
  UvSink sink{transforms.data(), static_cast<double>(map.atlas_width), static_cast<double>(map.atlas_height),
              corner_uv.data()};
  if (const LayoutStatus ls = layout_patches(mesh, map.patch_of_face, map.patch_count, &UvSink::emit, &sink,
                                             map.seeds, map.methods, map.solve);
      ls != LayoutStatus::ok)
    return from_layout_status(ls);
  return UvStatus::ok;
}

}  // namespace gltfwarp
