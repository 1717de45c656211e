// The encoder's quality check: identical textures on identical UVs measure
// 99 dB, a half-texel shift of a sharp texture measures far less, a large
// mesh is measured within its point budget, and the figures do not depend on
// how many threads measure them.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include "codec/encode/texture/mip_quality.h"
#include "codec/encode/texture/warp_quality.h"

namespace gltfwarp {
namespace {

OIIO::ImageBuf checker(int n, int cell) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(n, n, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int c = 0; c < 3; ++c) p[(size_t(y) * n + x) * 3 + c] = ((x / cell + y / cell) % 2) ? 230 : 20;
  return buf;
}

// Two triangles covering the unit square, shifted by (dx, dy).
std::vector<float> square(float dx, float dy) {
  return {0 + dx, 0 + dy, 1 + dx, 0 + dy, 1 + dx, 1 + dy, 0 + dx, 0 + dy, 1 + dx, 1 + dy, 0 + dx, 1 + dy};
}

TEST(WarpQuality, IdenticalIs99AndAShiftIsSeen) {
  TextureSampler a, b;
  const std::array<double, 6> id{1, 0, 0, 0, 1, 0};
  load_texture_sampler(checker(64, 1), true, 33071, 33071, id, a);
  load_texture_sampler(checker(64, 1), true, 33071, 33071, id, b);
  const std::vector<float> uv = square(0, 0), shifted = square(0.5f / 64, 0);
  const SurfaceUvs same[] = {{uv, uv, {}, {}}};
  const SurfaceError e = surface_error(a, b, same);
  EXPECT_GT(e.values, 3u * 64 * 64 / 2) << "about one point per texel";
  EXPECT_EQ(e.psnr(), 99.0);
  const SurfaceUvs off[] = {{uv, shifted, {}, {}}};
  EXPECT_LT(surface_error(a, b, off).psnr(), 20.0) << "half a texel on a 1-texel checker";
  // The source transform is applied: a source scaled 2x about 0 samples like
  // the atlas at double the UVs.
  TextureSampler scaled;
  load_texture_sampler(checker(64, 1), true, 33071, 33071, {0.5, 0, 0, 0, 0.5, 0}, scaled);
  const std::vector<float> doubled = square(0, 0),
                           half = {0, 0, 0.5f, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0.5f};
  const SurfaceUvs tx[] = {{doubled, half, {}, {}}};
  EXPECT_EQ(surface_error(scaled, b, tx).psnr(), 99.0);
}

// Rate control measures one group's faces against one source dozens of
// times: the source's values at the points are kept (SourceSamples) and
// only the atlas side is sampled again. The figures must be the same bits
// as a measure that samples both, for every atlas, also when a budget
// thins the faces (fewer points: the kept values are sampled again).
TEST(WarpQuality, KeptSourceSamplesGiveTheSameFigures) {
  TextureSampler source, near_copy, shifted_copy;
  const std::array<double, 6> id{1, 0, 0, 0, 1, 0};
  load_texture_sampler(checker(64, 3), true, 33071, 33071, id, source);
  load_texture_sampler(checker(64, 3), true, 33071, 33071, id, near_copy);
  load_texture_sampler(checker(64, 2), true, 33071, 33071, id, shifted_copy);
  const std::vector<float> uv = square(0, 0), moved = square(0.3f / 64, 0.1f / 64);
  const SurfaceUvs on_uv[] = {{uv, moved, {}, {}}};
  SourceSamples kept;
  for (const TextureSampler* atlas : {&near_copy, &shifted_copy, &near_copy})
    for (uint64_t budget : {uint64_t(4'000'000), uint64_t(500), uint64_t(4'000'000)}) {
      std::vector<SurfaceError> plain_groups, kept_groups;
      const SurfaceError plain = surface_error(source, *atlas, on_uv, budget, &plain_groups);
      const SurfaceError cached = surface_error(source, *atlas, on_uv, budget, &kept_groups, &kept);
      EXPECT_EQ(plain.squared, cached.squared) << "budget " << budget;
      EXPECT_EQ(plain.values, cached.values);
      EXPECT_EQ(plain.points, cached.points);
      ASSERT_EQ(plain_groups.size(), kept_groups.size());
      EXPECT_LT(plain.psnr(), 60.0) << "precondition: the atlas differs from the source";
    }
  ASSERT_EQ(kept.prims.size(), 1u);
  EXPECT_EQ(kept.prims.begin()->second.size(), 2u) << "one entry per face";
}

TEST(WarpQuality, PointBudgetSpreadsOverFaces) {
  TextureSampler a;
  load_texture_sampler(checker(256, 8), false, 10497, 10497, {1, 0, 0, 0, 1, 0}, a);
  std::vector<float> uv;
  for (int i = 0; i < 2000; ++i) {
    const std::vector<float> s = square(float(i % 7) / 7, 0);
    uv.insert(uv.end(), s.begin(), s.end());
  }
  const SurfaceUvs prims[] = {{uv, uv, {}, {}}};
  const SurfaceError e = surface_error(a, a, prims, 100'000);
  EXPECT_LE(e.points, 100'000u);
  EXPECT_GT(e.points, 20'000u);
  // 4000 faces of 32768 texels each, 64 x 64 points in full: the thinned
  // points weigh as much as the full ones would.
  EXPECT_NEAR(e.values, 3.0 * 4000 * 64 * 64, 1e-6 * e.values);
  EXPECT_EQ(e.psnr(), 99.0);
  EXPECT_EQ(surface_error(a, TextureSampler{}, prims).values, 0u) << "an unloaded sampler measures nothing";
}

// Where the error sits in a few faces, a measure over a point budget still
// finds it: every face keeps some points. Skipping faces by a stride (as
// the measure once did: every 85th face here) never visited these (faces
// 1, 41, 81, ...) and read 99 dB.
TEST(WarpQuality, ThinnedMeasureFindsErrorInFewFaces) {
  TextureSampler a;
  load_texture_sampler(checker(64, 2), false, 10497, 10497, {1, 0, 0, 0, 1, 0}, a);
  std::vector<float> uv, moved;
  for (int i = 0; i < 1000; ++i) {
    // Each square at its own offset into the (repeating) checker, so that
    // thinned points meet its edges at many phases, as on a real mesh.
    const float du = float(i % 97) / 97, dv = float(i % 89) / 89;
    const std::vector<float> s = square(du, dv), m = square(du + (i % 20 == 0 ? 1.0f / 64 : 0), dv);
    uv.insert(uv.end(), s.begin(), s.end());
    // Only the second face of every 20th square moves: faces 1, 41, 81, ...
    moved.insert(moved.end(), s.begin(), s.begin() + 6);
    moved.insert(moved.end(), m.begin() + 6, m.end());
  }
  const SurfaceUvs prims[] = {{uv, moved, {}, {}}};
  const SurfaceError full = surface_error(a, a, prims, 100'000'000),
                     thinned = surface_error(a, a, prims, 50'000);
  ASSERT_LT(full.psnr(), 40.0);
  EXPECT_LT(thinned.points, full.points / 50);
  EXPECT_NEAR(thinned.psnr(), full.psnr(), 0.5);
  const MipQuality mip_full = mip_surface_error(a, a, prims, {100'000'000}),
                   mip_thinned = mip_surface_error(a, a, prims, {50'000});
  for (int l = 0; l < kMipLevels; ++l)
    EXPECT_NEAR(mip_thinned.level[l].psnr(), mip_full.level[l].psnr(), 0.5) << "level " << l;
}

// Per-group errors (per patch in the encoder) add up to the total, and a
// shift on one face only shows in that face's group.
TEST(WarpQuality, PerGroupErrorsAddUp) {
  TextureSampler a;
  load_texture_sampler(checker(64, 1), true, 33071, 33071, {1, 0, 0, 0, 1, 0}, a);
  std::vector<float> uv = square(0, 0), moved = square(0, 0);
  for (int i = 6; i < 12; i += 2) moved[size_t(i)] += 0.5f / 64;  // second face shifted half a texel
  const std::vector<uint32_t> groups = {3, 1};
  const SurfaceUvs prims[] = {{uv, moved, groups, {}}};
  std::vector<SurfaceError> per;
  const SurfaceError total = surface_error(a, a, prims, 4'000'000, &per);
  ASSERT_EQ(per.size(), 4u);
  EXPECT_EQ(per[3].squared, 0.0);
  EXPECT_GT(per[1].squared, 0.0);
  EXPECT_EQ(per[0].values + per[2].values, 0u);
  EXPECT_EQ(per[1].values + per[3].values, total.values);
  EXPECT_DOUBLE_EQ(per[1].squared, total.squared);
}

// The encoder's decisions compare these figures with thresholds, so they
// must be the same bits on a 2-core CI machine and a 64-core workstation:
// faces are measured in parallel but summed in one order.
TEST(WarpQuality, FiguresDoNotDependOnTheThreadCount) {
  TextureSampler source, atlas;
  load_texture_sampler(checker(256, 3), true, 10497, 10497, {1, 0, 0, 0, 1, 0}, source);
  load_texture_sampler(checker(128, 2), true, 33071, 33071, {1, 0, 0, 0, 1, 0}, atlas);
  std::vector<float> su, au;
  std::vector<uint32_t> groups;
  for (int i = 0; i < 3000; ++i) {  // slightly different maps: every face has its own error
    const float t = float(i % 97) / 97, k = 1 + float(i % 13) / 50;
    const float s[] = {t, 0, t + 0.2f, 0, t, 0.2f}, a[] = {t * k, 0.01f, (t + 0.2f) * k, 0, t, 0.2f * k};
    su.insert(su.end(), s, s + 6);
    au.insert(au.end(), a, a + 6);
    groups.push_back(uint32_t(i % 50));
  }
  const SurfaceUvs prims[] = {{su, au, groups, {}}};
  auto measure = [&](int threads, std::vector<SurfaceError>& per, MipQuality& mip) {
    int before = 0;
    OIIO::getattribute("threads", before);
    OIIO::attribute("threads", threads);
    const SurfaceError e = surface_error(source, atlas, prims, 4'000'000, &per);
    mip = mip_surface_error(source, atlas, prims);
    OIIO::attribute("threads", before);
    return e;
  };
  std::vector<SurfaceError> per1, per8;
  MipQuality mip1, mip8;
  const SurfaceError one = measure(1, per1, mip1), eight = measure(8, per8, mip8);
  ASSERT_GT(one.values, 0u);
  EXPECT_GT(one.squared, 0.0);
  EXPECT_EQ(one.squared, eight.squared);  // bit for bit, not nearly
  EXPECT_EQ(one.values, eight.values);
  ASSERT_EQ(per1.size(), per8.size());
  for (size_t g = 0; g < per1.size(); ++g) EXPECT_EQ(per1[g].squared, per8[g].squared) << "group " << g;
  for (int l = 0; l < kMipLevels; ++l) {
    EXPECT_GT(mip1.level[l].values, 0u);
    EXPECT_EQ(mip1.level[l].squared, mip8.level[l].squared) << "level " << l;
    EXPECT_EQ(mip1.worst_psnr[l], mip8.worst_psnr[l]) << "level " << l;
  }
}

}  // namespace
}  // namespace gltfwarp
