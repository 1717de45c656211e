// The texels triangles reach, and the reference that ignores the rest: the
// quality at MIP levels must not depend on what a source holds where no
// face samples it (its chart bleed is not the atlas's to copy).
#include <gtest/gtest.h>

#include "codec/encode/texture/mip_quality.h"
#include "codec/encode/texture/texel_reach.h"
#include "support/noise_image.h"

namespace gltfwarp {
namespace {

// Texels at least `margin` texels from the triangle (0.1,0.1) (0.6,0.1) (0.1,0.6) of an n x n texture.
bool far_outside(int x, int y, int n, double margin) {
  const double u = (x + 0.5) / n, v = (y + 0.5) / n;
  return u + v > 0.7 + margin * 1.5 / n || u < 0.1 - margin / n || v < 0.1 - margin / n;
}

const std::vector<float> kTriangle = {0.1f, 0.1f, 0.6f, 0.1f, 0.1f, 0.6f};

TEST(TexelReach, FillsOnlyTheTexelsNoTriangleReaches) {
  const int n = 64;
  TextureSampler t;
  load_texture_sampler(test::noise_image(n, 3), false, 33071, 33071, {1, 0, 0, 0, 1, 0}, t);
  const TextureSampler filled = with_unreached_filled(t, kTriangle);
  const auto* a = static_cast<const float*>(t.pixels.localpixels());
  const auto* b = static_cast<const float*>(filled.pixels.localpixels());
  size_t kept = 0, changed_far = 0, far = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const size_t i = (size_t(y) * n + x) * 3;
      const bool same = a[i] == b[i] && a[i + 1] == b[i + 1] && a[i + 2] == b[i + 2];
      const double u = (x + 0.5) / n, v = (y + 0.5) / n;
      if (u >= 0.1 && v >= 0.1 && u + v <= 0.7) {
        kept += same ? 1 : 0;
        EXPECT_TRUE(same) << x << "," << y;
      }
      if (far_outside(x, y, n, 3)) ++far, changed_far += same ? 0 : 1;
    }
  EXPECT_GT(kept, 100u);
  EXPECT_GT(far, 1000u);
  EXPECT_GT(changed_far, far * 9 / 10) << "the unreached noise is replaced by the fill";
}

TEST(TexelReach, ATriangleSpanningTheTextureReachesEveryTexel) {
  TexelReach reach(32, 32, OIIO::ImageBuf::WrapPeriodic, OIIO::ImageBuf::WrapPeriodic);
  const std::vector<float> tiled = {0, 0, 30, 0, 0, 30};
  reach.add_triangles(tiled, {1, 0, 0, 0, 1, 0});
  EXPECT_TRUE(reach.all_reached());
  EXPECT_EQ(reach.reached(), 32u * 32u);
}

TEST(TexelReach, MipQualityIgnoresWhatTheSourceHoldsWhereNoFaceSamples) {
  const int n = 128;
  const OIIO::ImageBuf img = test::noise_image(n, 11), other = test::noise_image(n, 12);
  OIIO::ImageBuf repainted = img;  // img with every texel far from the triangle replaced
  auto* p = static_cast<uint8_t*>(repainted.localpixels());
  const auto* o = static_cast<const uint8_t*>(other.localpixels());
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (far_outside(x, y, n, 3))
        for (int c = 0; c < 3; ++c) p[(size_t(y) * n + x) * 3 + c] = o[(size_t(y) * n + x) * 3 + c];
  TextureSampler s1, s2, atlas;
  load_texture_sampler(img, true, 33071, 33071, {1, 0, 0, 0, 1, 0}, s1);
  load_texture_sampler(repainted, true, 33071, 33071, {1, 0, 0, 0, 1, 0}, s2);
  load_texture_sampler(test::noise_image(n, 13), true, 33071, 33071, {1, 0, 0, 0, 1, 0}, atlas);
  const std::vector<uint32_t> patch = {0};
  const SurfaceUvs prims[] = {{kTriangle, kTriangle, patch, {}}};
  const MipQuality q1 = mip_surface_error(s1, atlas, prims), q2 = mip_surface_error(s2, atlas, prims);
  for (int l = 0; l < kMipLevels; ++l) {
    EXPECT_GT(q1.level[l].values, 0u);
    EXPECT_DOUBLE_EQ(q1.level[l].psnr(), q2.level[l].psnr()) << "level " << l;
  }
}

}  // namespace
}  // namespace gltfwarp
