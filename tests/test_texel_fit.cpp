// Least-squares texels: a fitted atlas reconstructs its source better than
// point samples at the same texel count, a constant stays exactly constant,
// and a texel no sample reaches keeps its warm start.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "codec/encode/texture/texel_fit.h"
#include "codec/encode/texture/texture_sampler.h"
#include "codec/encode/texture/warp.h"
#include "codec/encode/texture/warp_quality.h"

namespace gltfwarp {
namespace {

// Samples at n x n points of every texel of a w x h image, target f(x, y).
template <class F>
void dense_samples(int w, int h, int n, F f, std::vector<float>& xy, std::vector<float>& weight,
                   std::vector<float>& target) {
  for (int y = 0; y < h * n; ++y)
    for (int x = 0; x < w * n; ++x) {
      const float px = (x + 0.5f) / n, py = (y + 0.5f) / n;
      xy.push_back(px), xy.push_back(py);
      weight.push_back(1.0f / float(n * n));
      target.push_back(f(px, py));
    }
}

TEST(TexelFit, ConstantStaysExactlyConstant) {
  const int w = 16, h = 12;
  std::vector<float> xy, weight, target;
  dense_samples(
      w, h, 3, [](float, float) { return 0.375f; }, xy, weight, target);
  std::vector<float> texels(size_t(w) * h, 0.375f);
  TexelFitReport r;
  ASSERT_EQ(fit_texels(w, h, 1, xy, weight, target, texels, {}, &r), TexelFitStatus::ok);
  EXPECT_EQ(r.fitted_texels, uint64_t(w) * h);
  for (float v : texels) EXPECT_EQ(v, 0.375f);
}

TEST(TexelFit, UnreachedTexelKeepsWarmStartAndReachedOnesImprove) {
  const int w = 32, h = 32;
  std::vector<float> xy, weight, target;
  // A sharp edge on the left half only; the right half (x >= 20) has no samples.
  auto edge = [](float x, float y) { return (x + 0.5f * y) < 14 ? 0.1f : 0.9f; };
  dense_samples(16, h, 4, edge, xy, weight, target);
  std::vector<float> texels(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) texels[size_t(y) * w + x] = edge(x + 0.5f, y + 0.5f);
  texels[size_t(5) * w + 25] = 0.123f;  // far from every sample's stencil
  std::vector<uint8_t> unknown(size_t(w) * h, 0);
  TexelFitReport r;
  ASSERT_EQ(fit_texels(w, h, 1, xy, weight, target, texels, {}, &r, unknown), TexelFitStatus::ok);
  EXPECT_EQ(texels[size_t(5) * w + 25], 0.123f);
  EXPECT_EQ(unknown[size_t(5) * w + 25], 0);
  EXPECT_EQ(unknown[size_t(5) * w + 16], 1) << "the texel right of the sampled area is reached";
  EXPECT_EQ(unknown[size_t(5) * w + 17], 0);
  EXPECT_GT(r.gain_db(), 0.3) << "the fit undoes part of the bilinear blur at the edge";
  for (float v : texels) EXPECT_TRUE(v >= 0 && v <= 1);
}

TEST(TexelFit, BadInput) {
  std::vector<float> xy{0.5f, 0.5f}, weight{1}, target{0.5f}, texels(4);
  EXPECT_EQ(fit_texels(2, 2, 2, xy, weight, target, texels), TexelFitStatus::bad_input);
  EXPECT_EQ(fit_texels(0, 2, 1, xy, weight, target, texels), TexelFitStatus::bad_input);
  EXPECT_EQ(fit_texels(2, 2, 1, xy, weight, target, texels), TexelFitStatus::ok);
}

// A rotated, slightly magnified square patch of a detailed texture: the
// warp with and without the fit, measured as a viewer sees both.
struct RotatedPatch {
  std::vector<float> src, atlas;
  RotatedPatch(int W, double degrees, double scale) {
    const double a = degrees * 3.14159265358979 / 180, c = std::cos(a), s = std::sin(a);
    const int n = 8;
    auto put = [&](double i, double j) {
      const double u = 0.1 + 0.8 * i, v = 0.1 + 0.8 * j;
      const double x = (u - 0.5) * scale, y = (v - 0.5) * scale;
      atlas.push_back(float((c * x - s * y) * 0.9 + 0.5)),
          atlas.push_back(float((s * x + c * y) * 0.9 + 0.5));
      src.push_back(float(u)), src.push_back(float(v));
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double i0 = double(i) / n, i1 = double(i + 1) / n, j0 = double(j) / n, j1 = double(j + 1) / n;
        put(i0, j0), put(i1, j0), put(i1, j1);
        put(i0, j0), put(i1, j1), put(i0, j1);
      }
    (void)W;
  }
};

OIIO::ImageBuf detailed(int n) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(n, n, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double v =
          0.5 + 0.25 * std::sin(x * 0.9) * std::cos(y * 0.7) + 0.2 * (((x / 5 + y / 7) & 1) ? 1 : -1);
      p[(size_t(y) * n + x) * 3 + 0] = uint8_t(std::lround(255 * std::clamp(v, 0.0, 1.0)));
      p[(size_t(y) * n + x) * 3 + 1] = uint8_t((x * 37 + y * 11) & 255);
      p[(size_t(y) * n + x) * 3 + 2] = uint8_t(((x / 3) & 1) ? 200 : 40);
    }
  return buf;
}

double warped_psnr(const OIIO::ImageBuf& source, const RotatedPatch& patch, int W, bool least_squares,
                   WarpReport* report = nullptr) {
  WarpPrimitive wp;
  wp.source_uv = patch.src;
  wp.atlas_uv = patch.atlas;
  const WarpPrimitive prims[1] = {wp};
  WarpOptions opt;
  opt.least_squares = least_squares;
  opt.wrap_s = opt.wrap_t = WrapMode::clamp_to_edge;
  OIIO::ImageBuf out;
  EXPECT_EQ(warp_texture(source, prims, W, W, opt, out, report), WarpStatus::ok);
  TextureSampler before, after;
  load_texture_sampler(source, true, 33071, 33071, {1, 0, 0, 0, 1, 0}, before);
  load_texture_sampler(out, true, 33071, 33071, {1, 0, 0, 0, 1, 0}, after);
  const SurfaceUvs uvs[1] = {{patch.src, patch.atlas, {}, {}}};
  return surface_error(before, after, uvs).psnr();
}

TEST(TexelFit, FittedAtlasBeatsPointSamplingAtEqualTexels) {
  const int S = 96, W = 112;
  const OIIO::ImageBuf source = detailed(S);
  const RotatedPatch patch(W, 23, 1.0);
  const double point = warped_psnr(source, patch, W, false);
  WarpReport r;
  const double fitted = warped_psnr(source, patch, W, true, &r);
  EXPECT_GT(r.fit.fitted_texels, 0u);
  EXPECT_GT(r.fit.gain_db(), 0.0);
  EXPECT_GT(fitted, point + 0.5) << "point " << point << " dB, fitted " << fitted << " dB";
}

TEST(TexelFit, ConstantSourceWarpsToExactlyConstantAtlas) {
  OIIO::ImageBuf flat(OIIO::ImageSpec(32, 32, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(flat.localpixels());
  for (int i = 0; i < 32 * 32; ++i) p[3 * i] = 17, p[3 * i + 1] = 130, p[3 * i + 2] = 201;
  const RotatedPatch patch(64, 31, 1.3);
  WarpPrimitive wp;
  wp.source_uv = patch.src;
  wp.atlas_uv = patch.atlas;
  const WarpPrimitive prims[1] = {wp};
  OIIO::ImageBuf out;
  WarpReport r;
  WarpOptions opt;
  opt.least_squares = true;  // opt-in (EncodeOptions::least_squares_texels)
  ASSERT_EQ(warp_texture(flat, prims, 64, 64, opt, out, &r), WarpStatus::ok);
  EXPECT_GT(r.fit.fitted_texels, 0u);
  const auto* q = static_cast<const uint8_t*>(out.localpixels());
  for (int i = 0; i < 64 * 64; ++i) {
    ASSERT_EQ(q[3 * i], 17) << i;
    ASSERT_EQ(q[3 * i + 1], 130) << i;
    ASSERT_EQ(q[3 * i + 2], 201) << i;
  }
}

}  // namespace
}  // namespace gltfwarp
