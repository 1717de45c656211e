// Texel reuse (issue 16, item 2; format 1.3): a model built symmetric whose
// halves show the same source texels stores them once. Generated here: a
// gently curved grid and its mirror image (x negated, winding reversed) with
// the same UVs, as a modeller's mirror modifier makes it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

#include "codec/decode/decoder.h"
#include "codec/encode/encoder.h"
#include "codec/encode/partition/twin_partition.h"
#include "format/gltf/gltf_primitive.h"
#include "support/malformed.h"

namespace gltfwarp {
namespace {

tinygltf::Model mirrored_grid(bool mirror) {
  test::MeshSpec half = test::grid_mesh(24, 16);
  test::MeshSpec other = half;
  for (size_t v = 0; v < other.positions.size(); v += 3) other.positions[v] = -other.positions[v] - 0.02f;
  if (mirror)
    for (size_t f = 0; f < other.indices.size(); f += 3)
      std::swap(other.indices[f + 1], other.indices[f + 2]);
  test::append_mesh(half, other);
  tinygltf::Model m = test::empty_scene();
  const int image = test::add_gradient_png_image(m, 256);
  test::add_primitive(m, half, test::add_material(m, test::add_texture(m, image)));
  return m;
}

struct Encoded {
  tinygltf::Model model;
  EncodeReport report;
};

Encoded encode(bool reuse) {
  Encoded e;
  e.model = mirrored_grid(true);
  EncodeOptions o;
  o.texel_reuse = reuse;
  o.texel_density = 200;  // fixed: both encodes at the same detail
  o.adaptive_density = false;
  o.quality_fallback = false;
  EXPECT_EQ(encode_model(e.model, o, e.report).message, "");
  return e;
}

uint64_t atlas_texels(const EncodeReport& r) {
  uint64_t t = 0;
  for (const auto& a : r.atlases)
    for (const auto& p : a.page_sizes) t += uint64_t(p[0]) * p[1];
  return t;
}

TEST(TexelReuse, FindsTheMirroredHalfFaceByFace) {
  const tinygltf::Model m = mirrored_grid(true);
  PrimitiveGeometry g;
  ASSERT_EQ(read_primitive(m, m.meshes[0].primitives[0], g), "");
  TriMesh mesh;
  mesh.positions = g.find("POSITION")->to_floats();
  mesh.indices = g.triangles;
  const std::vector<float> uv = g.find("TEXCOORD_0")->to_floats();
  std::vector<float> corner_uv;
  for (uint32_t v : mesh.indices) corner_uv.insert(corner_uv.end(), {uv[2 * v], uv[2 * v + 1]});
  const FaceTwins t = find_face_twins(mesh, corner_uv);
  const uint32_t half = mesh.face_count() / 2;
  EXPECT_EQ(t.copies, half);
  for (uint32_t f = half; f < mesh.face_count(); ++f) {
    ASSERT_EQ(t.primary[f], f - half);
    for (int k = 0; k < 3; ++k) {
      const uint32_t c = t.twin_corner[3 * f + k];
      EXPECT_EQ(corner_uv[2 * c], corner_uv[6 * f + 2 * k]);
      EXPECT_EQ(corner_uv[2 * c + 1], corner_uv[6 * f + 2 * k + 1]);
    }
  }
}

TEST(TexelReuse, MirroredHalvesShareOneAtlasRegion) {
  Encoded with = encode(true), without = encode(false);
  ASSERT_EQ(with.report.atlases.size(), 1u);
  ASSERT_EQ(without.report.atlases.size(), 1u);
  const AtlasReport& a = with.report.atlases[0];
  EXPECT_GT(a.reused_patches, 0u);
  EXPECT_EQ(without.report.atlases[0].reused_patches, 0u);
  EXPECT_EQ(a.overlapping_texels, 0u);
  std::printf("texel reuse: %u copies, %llu atlas texels against %llu without, %.2f dB against %.2f dB\n",
              a.reused_patches, (unsigned long long)atlas_texels(with.report),
              (unsigned long long)atlas_texels(without.report), a.psnr, without.report.atlases[0].psnr);
  for (const AtlasReport* r : std::array<const AtlasReport*, 2>{&a, &without.report.atlases[0]})
    std::printf("  MIP 0-3 mean %.1f %.1f %.1f %.1f, worst 1%% %.1f %.1f %.1f %.1f\n", r->mip_psnr[0],
                r->mip_psnr[1], r->mip_psnr[2], r->mip_psnr[3], r->worst_psnr[0], r->worst_psnr[1],
                r->worst_psnr[2], r->worst_psnr[3]);
  // The bar: at most 0.6x the texels of the same model without reuse.
  EXPECT_LE(double(atlas_texels(with.report)), 0.6 * double(atlas_texels(without.report)))
      << atlas_texels(with.report) << " against " << atlas_texels(without.report);
  // The quality a viewer sees holds (the copies read their originals' texels).
  EXPECT_GE(a.psnr, without.report.atlases[0].psnr - 1.0);

  // Decoded: each vertex of the mirrored half has its twin's UV (to a
  // fraction of a texel), so both halves sample one region.
  DecodeReport dr;
  ASSERT_EQ(decode_model(with.model, DecodeOptions{}, dr).message, "");
  PrimitiveGeometry g;
  ASSERT_EQ(read_primitive(with.model, with.model.meshes[0].primitives[0], g), "");
  const std::vector<float> pos = g.find("POSITION")->to_floats();
  const std::vector<float> uv = g.find("TEXCOORD_0")->to_floats();
  const double texel = 1.0 / std::max(a.width, a.height);
  // A vertex on a seam is split, one UV per patch: a copy's vertex matches
  // one of its twin's.
  std::multimap<std::tuple<long, long, long>, size_t> original;
  auto key = [&](size_t v, bool mirrored) {
    const double x = mirrored ? -pos[3 * v] - 0.02 : pos[3 * v];
    return std::tuple{std::lround(x * 1024), std::lround(pos[3 * v + 1] * 1024),
                      std::lround(pos[3 * v + 2] * 1024)};
  };
  for (size_t v = 0; v < pos.size() / 3; ++v)
    if (pos[3 * v] >= 0) original.emplace(key(v, false), v);
  size_t matched = 0, close = 0;
  for (size_t v = 0; v < pos.size() / 3; ++v) {
    if (pos[3 * v] >= 0) continue;
    const auto [lo, hi] = original.equal_range(key(v, true));
    if (lo == hi) continue;
    ++matched;
    double best = 1e9;
    for (auto it = lo; it != hi; ++it)
      best = std::min(best, std::hypot(double(uv[2 * v]) - uv[2 * it->second],
                                       double(uv[2 * v + 1]) - uv[2 * it->second + 1]));
    if (best <= 0.5 * texel) ++close;
  }
  EXPECT_GT(matched, pos.size() / 3 / 4) << "mirrored vertices found by position";
  EXPECT_GE(double(close), 0.95 * double(matched)) << close << " of " << matched << " within half a texel";
}

}  // namespace
}  // namespace gltfwarp
