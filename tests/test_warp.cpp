// Warp: a checkerboard survives a rotation, smooth content survives a
// minifying turn, wrap modes, sRGB round trip, gutters never bleed, normal
// maps are re-expressed in the new tangent frame.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <set>

#include "codec/decode/tangents.h"
#include "codec/encode/texture/warp.h"

namespace gltfwarp {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Fn = std::function<void(int x, int y, uint8_t* px)>;

OIIO::ImageBuf make_image(int w, int h, int nch, const Fn& fn) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, nch, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) fn(x, y, p + (size_t(y) * w + x) * nch);
  return buf;
}

const uint8_t* texel(const OIIO::ImageBuf& img, int x, int y) {
  const auto& s = img.spec();
  return static_cast<const uint8_t*>(img.localpixels()) + (size_t(y) * s.width + x) * s.nchannels;
}

// A parallelogram patch split into n x n quads: atlas corner a0 + i*ax + j*ay
// (texels) carries source uv s0 + i*sx + j*sy, i, j in [0, 1].
struct Patch {
  std::vector<float> src, atlas;
  void add(double a0x, double a0y, double axx, double axy, double ayx, double ayy,  //
           double s0u, double s0v, double sxu, double sxv, double syu, double syv, int W, int H, int n = 4) {
    auto put = [&](double i, double j) {
      atlas.push_back(float((a0x + i * axx + j * ayx) / W));
      atlas.push_back(float((a0y + i * axy + j * ayy) / H));
      src.push_back(float(s0u + i * sxu + j * syu));
      src.push_back(float(s0v + i * sxv + j * syv));
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double i0 = double(i) / n, i1 = double(i + 1) / n, j0 = double(j) / n, j1 = double(j + 1) / n;
        put(i0, j0), put(i1, j0), put(i1, j1);
        put(i0, j0), put(i1, j1), put(i0, j1);
      }
  }
  WarpPrimitive view() const {
    WarpPrimitive p;
    p.source_uv = src;
    p.atlas_uv = atlas;
    return p;
  }
};

TEST(Warp, CheckerboardSurvivesRotation) {
  const int S = 256;
  const OIIO::ImageBuf src = make_image(
      S, S, 3, [](int x, int y, uint8_t* p) { p[0] = p[1] = p[2] = ((x / 16 + y / 16) & 1) ? 255 : 0; });
  const int W = 320;
  const double a = 30 * kPi / 180, c = std::cos(a), s = std::sin(a);
  // Source texel q in [32, 224]^2 goes to R(a) (q - 128) + 160.
  auto to_atlas = [&](double qx, double qy, double& x, double& y) {
    x = c * (qx - 128) - s * (qy - 128) + 160;
    y = s * (qx - 128) + c * (qy - 128) + 160;
  };
  double x0, y0, x1, y1, x2, y2;
  to_atlas(32, 32, x0, y0);
  to_atlas(224, 32, x1, y1);
  to_atlas(32, 224, x2, y2);
  Patch patch;
  patch.add(x0, y0, x1 - x0, y1 - y0, x2 - x0, y2 - y0, 32.0 / S, 32.0 / S, 192.0 / S, 0, 0, 192.0 / S, W, W,
            8);
  const WarpPrimitive prims[1] = {patch.view()};
  WarpOptions opt;
  opt.encoding = SlotEncoding::linear;
  OIIO::ImageBuf out;
  WarpReport rep;
  ASSERT_EQ(warp_texture(src, prims, W, W, opt, out, &rep), WarpStatus::ok) << rep.error;
  EXPECT_GT(rep.covered_texels, 190u * 190u);
  int checked = 0, bad = 0;
  double se = 0;
  for (int y = 0; y < W; ++y)
    for (int x = 0; x < W; ++x) {
      const double px = x + 0.5 - 160, py = y + 0.5 - 160;
      const double qx = c * px + s * py + 128, qy = -s * px + c * py + 128;
      if (qx < 34 || qy < 34 || qx > 222 || qy > 222) continue;
      const double ex = std::abs(std::fmod(qx, 16.0) - 8), ey = std::abs(std::fmod(qy, 16.0) - 8);
      const double expect = ((int(qx) / 16 + int(qy) / 16) & 1) ? 255 : 0;
      const double got = texel(out, x, y)[0];
      if (std::min(8 - ex, 8 - ey) < 1.5) continue;  // near a check edge: anti-aliased
      ++checked;
      se += (got - expect) * (got - expect);
      if (std::abs(got - expect) > 8) ++bad;
    }
  EXPECT_GT(checked, 20000);
  EXPECT_EQ(bad, 0);
  const double psnr = 10 * std::log10(255.0 * 255.0 / std::max(1e-9, se / checked));
  std::printf("checker interior PSNR %.1f dB over %d texels; %.2f Mtexel/s\n", psnr, checked,
              rep.texels_per_second * 1e-6);
  EXPECT_GT(psnr, 40);
}

TEST(Warp, SmoothContentSurvivesMinifyingTurn) {
  const int S = 512;
  auto f = [](double u, double v, int ch) {
    switch (ch) {
      case 0:
        return 0.5 + 0.4 * std::sin(2 * kPi * 2 * u);
      case 1:
        return 0.5 + 0.4 * std::cos(2 * kPi * 3 * v);
      default:
        return 0.2 + 0.6 * u * v;
    }
  };
  const OIIO::ImageBuf src = make_image(S, S, 3, [&](int x, int y, uint8_t* p) {
    for (int ch = 0; ch < 3; ++ch) p[ch] = uint8_t(std::lround(255 * f((x + 0.5) / S, (y + 0.5) / S, ch)));
  });
  // Whole source onto a 128x128 square turned by 90 degrees: atlas (x, y) =
  // (16 + 128 * (1 - v), 16 + 128 * u): minified by 4.
  const int W = 160;
  Patch patch;
  patch.add(16 + 128, 16, 0, 128, -128, 0, 0, 0, 1, 0, 0, 1, W, W);
  const WarpPrimitive prims[1] = {patch.view()};
  WarpOptions opt;
  opt.encoding = SlotEncoding::srgb;
  OIIO::ImageBuf out;
  ASSERT_EQ(warp_texture(src, prims, W, W, opt, out), WarpStatus::ok);
  double se = 0;
  int n = 0;
  for (int y = 18; y < 142; ++y)
    for (int x = 18; x < 142; ++x) {
      const double u = (y + 0.5 - 16) / 128, v = 1 - (x + 0.5 - 16) / 128;
      for (int ch = 0; ch < 3; ++ch) {
        const double d = texel(out, x, y)[ch] - 255 * f(u, v, ch);
        se += d * d, ++n;
      }
    }
  const double psnr = 10 * std::log10(255.0 * 255.0 / (se / n));
  std::printf("minified smooth PSNR %.1f dB\n", psnr);
  EXPECT_GT(psnr, 38);
}

TEST(Warp, CubicMagnificationIsSharperThanBilinear) {
  // A sinusoid of period 8 texels, read back at half-texel offsets (1:1, so
  // the lookup does not minify): bilinear interpolation flattens it, the
  // clamped Catmull-Rom cubic follows it closer and never leaves the range
  // of the nearest source texels.
  const int S = 64;
  auto wave = [](double p) { return 0.5 + 0.4 * std::sin(2 * kPi * (p - 0.5) / 8); };
  const OIIO::ImageBuf src =
      make_image(S, 8, 1, [&](int x, int, uint8_t* p) { p[0] = uint8_t(std::lround(255 * wave(x + 0.5))); });
  double rms[2];
  for (int cubic = 0; cubic < 2; ++cubic) {
    Patch patch;  // atlas [0, 64] x [0, 8] <- source u shifted by half a texel
    patch.add(0, 0, S, 0, 0, 8, 0.5 / S, 0, 1, 0, 0, 1, S, 8, 2);
    const WarpPrimitive prims[1] = {patch.view()};
    WarpOptions opt;
    opt.encoding = SlotEncoding::linear;
    opt.cubic_magnification = cubic == 1;
    OIIO::ImageBuf out;
    ASSERT_EQ(warp_texture(src, prims, S, 8, opt, out), WarpStatus::ok);
    double se = 0;
    int n = 0;
    for (int x = 4; x < S - 4; ++x, ++n) {
      const double got = texel(out, x, 4)[0] / 255.0;
      se += (got - wave(x + 1.0)) * (got - wave(x + 1.0));
      const double a = texel(src, x, 4)[0] / 255.0, b = texel(src, x + 1, 4)[0] / 255.0;
      EXPECT_GE(got, std::min(a, b) - 1.0 / 255) << x;
      EXPECT_LE(got, std::max(a, b) + 1.0 / 255) << x;
    }
    rms[cubic] = std::sqrt(se / n);
  }
  std::printf("half-texel sinusoid RMS error: bilinear %.4f, cubic %.4f\n", rms[0], rms[1]);
  EXPECT_LT(rms[1], 0.7 * rms[0]);
}

TEST(Warp, WrapModes) {
  // 16x16 source of 4x4 blocks: red = 20 + 60 * block column, green by block row.
  const OIIO::ImageBuf src = make_image(16, 16, 3, [](int x, int y, uint8_t* p) {
    p[0] = uint8_t(20 + 60 * (x / 4)), p[1] = uint8_t(20 + 60 * (y / 4)), p[2] = 100;
  });
  struct Case {
    WrapMode mode;
    int red;
  } cases[] = {{WrapMode::repeat, 80}, {WrapMode::mirrored_repeat, 140}, {WrapMode::clamp_to_edge, 200}};
  for (const Case& cs : cases) {
    Patch patch;  // a tiny source square around (1.375, 0.375) on atlas [8, 24]^2
    patch.add(8, 8, 16, 0, 0, 16, 1.37, 0.37, 0.01, 0, 0, 0.01, 32, 32, 1);
    const WarpPrimitive prims[1] = {patch.view()};
    WarpOptions opt;
    opt.encoding = SlotEncoding::linear;
    opt.wrap_s = cs.mode;
    opt.wrap_t = cs.mode;
    OIIO::ImageBuf out;
    ASSERT_EQ(warp_texture(src, prims, 32, 32, opt, out), WarpStatus::ok);
    EXPECT_NEAR(texel(out, 16, 16)[0], cs.red, 1) << int(cs.mode);
    EXPECT_NEAR(texel(out, 16, 16)[1], 80, 1) << int(cs.mode);
  }
  EXPECT_EQ(wrap_from_gltf(10497), WrapMode::repeat);
  EXPECT_EQ(wrap_from_gltf(33648), WrapMode::mirrored_repeat);
  EXPECT_EQ(wrap_from_gltf(33071), WrapMode::clamp_to_edge);
}

TEST(Warp, TextureTransformIsBaked) {
  // Transform maps the patch's uv (0..1) into the right half of the source.
  const OIIO::ImageBuf src =
      make_image(16, 16, 3, [](int x, int, uint8_t* p) { p[0] = x < 8 ? 10 : 240, p[1] = 0, p[2] = 0; });
  Patch patch;
  patch.add(4, 4, 24, 0, 0, 24, 0.2, 0.2, 0.6, 0, 0, 0.6, 32, 32, 2);
  const WarpPrimitive prims[1] = {patch.view()};
  WarpOptions opt;
  opt.encoding = SlotEncoding::linear;
  opt.wrap_s = opt.wrap_t = WrapMode::clamp_to_edge;
  const float m[6] = {0.3f, 0, 0.6f, 0, 1, 0};  // u' = 0.3 u + 0.6: in [0.66, 0.78]
  std::copy(m, m + 6, opt.uv_transform);
  OIIO::ImageBuf out;
  ASSERT_EQ(warp_texture(src, prims, 32, 32, opt, out), WarpStatus::ok);
  for (int y = 6; y < 26; ++y)
    for (int x = 6; x < 26; ++x) ASSERT_EQ(texel(out, x, y)[0], 240) << x << "," << y;
}

TEST(Warp, SrgbFlatColourRoundTripIsExact) {
  const OIIO::ImageBuf src =
      make_image(8, 8, 4, [](int, int, uint8_t* p) { p[0] = 200, p[1] = 37, p[2] = 90, p[3] = 128; });
  Patch patch;
  patch.add(3, 5, 20, 3, -4, 17, 0.1, 0.1, 0.8, 0, 0, 0.8, 32, 32);
  const WarpPrimitive prims[1] = {patch.view()};
  OIIO::ImageBuf out;
  WarpReport rep;
  ASSERT_EQ(warp_texture(src, prims, 32, 32, WarpOptions{}, out, &rep), WarpStatus::ok);
  ASSERT_EQ(out.spec().nchannels, 4);
  EXPECT_GT(rep.empty_texels, 0u);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const uint8_t* p = texel(out, x, y);
      ASSERT_EQ(p[0], 200);
      ASSERT_EQ(p[1], 37);
      ASSERT_EQ(p[2], 90);
      ASSERT_EQ(p[3], 128);
    }
}

// Two square patches in a 64 x 32 atlas (or a wider one): red at atlas x in
// [4, 20], blue at x in [28, 44], both at y in [8, 24], from a source whose
// left half is red and right half blue.
struct RedBlueScene {
  static constexpr int H = 32;
  int W = 64;
  OIIO::ImageBuf src = make_image(
      32, 16, 3, [](int x, int, uint8_t* p) { p[0] = x < 16 ? 255 : 0, p[1] = 0, p[2] = x < 16 ? 0 : 255; });
  Patch a, b;
  explicit RedBlueScene(int width = 64) : W(width) {
    a.add(4, 8, 16, 0, 0, 16, 0.1, 0.2, 0.3, 0, 0, 0.6, W, H);
    b.add(28, 8, 16, 0, 0, 16, 0.6, 0.2, 0.3, 0, 0, 0.6, W, H);
  }
};

TEST(Warp, GutterIsFilledAndNeverBleeds) {
  const RedBlueScene scene;
  const OIIO::ImageBuf& src = scene.src;
  const int W = scene.W, H = scene.H;
  const WarpPrimitive prims[2] = {scene.a.view(), scene.b.view()};
  WarpOptions opt;
  opt.gutter = 4;
  OIIO::ImageBuf out;
  WarpReport rep;
  ASSERT_EQ(warp_texture(src, prims, W, H, opt, out, &rep), WarpStatus::ok);
  EXPECT_GT(rep.gutter_texels, 0u);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const uint8_t* p = texel(out, x, y);
      const bool near_a = x >= 4 - 4 && x < 20 + 4 && y >= 8 - 4 && y < 24 + 4;
      const bool near_b = x >= 28 - 4 && x < 44 + 4 && y >= 8 - 4 && y < 24 + 4;
      if (near_a && x < 24) {
        ASSERT_EQ(p[0], 255) << x << "," << y;
        ASSERT_EQ(p[2], 0) << x << "," << y;
      } else if (near_b && x >= 24) {
        ASSERT_EQ(p[0], 0) << x << "," << y;
        ASSERT_EQ(p[2], 255) << x << "," << y;
      } else if (x > 52 || y < 3 || y > 28) {
        // far from both: the flat mean of covered texels (equal areas)
        ASSERT_NEAR(p[0], 128, 1) << x << "," << y;
        ASSERT_NEAR(p[2], 128, 1) << x << "," << y;
      }
    }
}

// EmptyFill::pull_push (JPEG atlases): the gutters are the same as with the
// flat fill, and beyond them each texel continues the patch nearest to it.
TEST(Warp, PullPushFillContinuesTheNearestPatch) {
  const RedBlueScene scene;
  const OIIO::ImageBuf& src = scene.src;
  const int W = scene.W, H = scene.H;
  const WarpPrimitive prims[2] = {scene.a.view(), scene.b.view()};
  WarpOptions flat, smooth;
  smooth.empty_fill = EmptyFill::pull_push;
  OIIO::ImageBuf out_flat, out_smooth;
  WarpReport rep;
  ASSERT_EQ(warp_texture(src, prims, W, H, flat, out_flat), WarpStatus::ok);
  ASSERT_EQ(warp_texture(src, prims, W, H, smooth, out_smooth, &rep), WarpStatus::ok);
  ASSERT_GT(rep.empty_texels, 0u);
  size_t changed = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const uint8_t* f = texel(out_flat, x, y);
      const uint8_t* p = texel(out_smooth, x, y);
      const bool near_a = x >= 0 && x < 24 && y >= 4 && y < 28;
      const bool near_b = x >= 24 && x < 48 && y >= 4 && y < 28;
      if (near_a || near_b) {  // patches and gutters: untouched
        ASSERT_EQ(std::vector<uint8_t>(f, f + 3), std::vector<uint8_t>(p, p + 3)) << x << "," << y;
        continue;
      }
      changed += p[0] != f[0] || p[2] != f[2];
      if (x < 14) {
        EXPECT_GT(p[0], p[2]) << x << "," << y << ": nearest to red";
      }
      if (x > 34) {
        EXPECT_GT(p[2], p[0]) << x << "," << y << ": nearest to blue";
      }
    }
  EXPECT_GT(changed, 0u);
}

// Beyond the patches the pull-push fill varies (red fading to blue), but
// each wholly empty 16x16 block of it is flat (flatten_empty_blocks): a
// block coder spends no AC coefficient where no viewer samples.
TEST(Warp, PullPushFillIsFlatOverEachWhollyEmptyBlock) {
  const RedBlueScene scene(128);  // 64 wholly empty columns beside the patches
  const int W = scene.W, H = scene.H;
  const WarpPrimitive prims[2] = {scene.a.view(), scene.b.view()};
  WarpOptions smooth;
  smooth.empty_fill = EmptyFill::pull_push;
  OIIO::ImageBuf out;
  ASSERT_EQ(warp_texture(scene.src, prims, W, H, smooth, out), WarpStatus::ok);
  std::set<uint32_t> block_colours;  // packed RGB
  for (int y0 = 0; y0 < H; y0 += 16)
    for (int x0 = 64; x0 < W; x0 += 16) {  // gutters end before x = 56
      const uint8_t* first = texel(out, x0, y0);
      block_colours.insert(uint32_t(first[0]) << 16 | uint32_t(first[1]) << 8 | first[2]);
      for (int y = y0; y < y0 + 16; ++y)
        for (int x = x0; x < x0 + 16; ++x) {
          const uint8_t* p = texel(out, x, y);
          ASSERT_EQ(std::vector<uint8_t>(p, p + 3), std::vector<uint8_t>(first, first + 3)) << x << "," << y;
        }
    }
  EXPECT_GT(block_colours.size(), 1u) << "the fill should vary from block to block";
}

// EmptyFill::nearest (PNG atlases): a viewer's MIP level L averages
// 2^L x 2^L blocks, which reach past a 4-texel gutter from level 3 on.
// Each block that meets one patch and not the other must then hold that
// patch's colour alone. The nearest copies reach 8 texels (level 3's
// block); in this scene the row runs beyond keep level 4 clean too. With
// the flat mean fill, blocks at level 4 mix the mean into the patch's
// border (checked too, so the scene can fail).
TEST(Warp, NearestFillKeepsEveryMipLevelOfAPatchBorderItsOwnColour) {
  const RedBlueScene scene(128);
  const int W = scene.W, H = scene.H;
  const WarpPrimitive prims[2] = {scene.a.view(), scene.b.view()};
  const auto mixed_blocks = [&](EmptyFill fill) {
    WarpOptions opt;
    opt.empty_fill = fill;
    OIIO::ImageBuf out;
    EXPECT_EQ(warp_texture(scene.src, prims, W, H, opt, out), WarpStatus::ok);
    int mixed = 0, checked = 0;
    for (int level = 1; level <= 4; ++level) {
      const int n = 1 << level;
      for (int y0 = 0; y0 < H; y0 += n)
        for (int x0 = 0; x0 < W; x0 += n) {
          // The patches' squares: red x in [4, 20), blue x in [28, 44), y in [8, 24).
          const bool rows = y0 < 24 && y0 + n > 8;
          const bool red = rows && x0 < 20 && x0 + n > 4, blue = rows && x0 < 44 && x0 + n > 28;
          if (red == blue) continue;
          ++checked;
          bool pure = true;
          for (int y = y0; y < y0 + n; ++y)
            for (int x = x0; x < x0 + n; ++x) {
              const uint8_t* p = texel(out, x, y);
              pure = pure && p[0] == (red ? 255 : 0) && p[1] == 0 && p[2] == (red ? 0 : 255);
            }
          mixed += !pure;
        }
    }
    EXPECT_GT(checked, 20);
    return mixed;
  };
  EXPECT_EQ(mixed_blocks(EmptyFill::nearest), 0);
  EXPECT_GT(mixed_blocks(EmptyFill::mean), 0);
}

// Normal maps: frames with the same normal, the new tangent turned by `a`.
uint8_t enc(double v) { return uint8_t(std::lround((v * 0.5 + 0.5) * 255)); }

void warp_normal(double nx, double ny, double nz, double a, uint8_t out_px[3]) {
  const OIIO::ImageBuf src =
      make_image(8, 8, 3, [&](int, int, uint8_t* p) { p[0] = enc(nx), p[1] = enc(ny), p[2] = enc(nz); });
  Patch patch;
  patch.add(4, 4, 24, 0, 0, 24, 0.1, 0.1, 0.8, 0, 0, 0.8, 32, 32, 2);
  const size_t corners = patch.atlas.size() / 2;
  std::vector<float> normals, oldt, newt;
  for (size_t c = 0; c < corners; ++c) {
    normals.insert(normals.end(), {0, 0, 1});
    oldt.insert(oldt.end(), {1, 0, 0, 1});
    newt.insert(newt.end(), {float(std::cos(a)), float(std::sin(a)), 0, 1});
  }
  WarpPrimitive p = patch.view();
  p.normals = normals;
  p.old_tangents = oldt;
  p.new_tangents = newt;
  const WarpPrimitive prims[1] = {p};
  WarpOptions opt;
  opt.encoding = SlotEncoding::normal;
  OIIO::ImageBuf out;
  ASSERT_EQ(warp_texture(src, prims, 32, 32, opt, out), WarpStatus::ok);
  std::copy(texel(out, 16, 16), texel(out, 16, 16) + 3, out_px);
}

TEST(Warp, FlatNormalMapStaysFlat) {
  for (double a : {0.0, 0.5, kPi / 2, 2.0, kPi, 4.5}) {
    uint8_t px[3];
    warp_normal(0, 0, 1, a, px);
    EXPECT_NEAR(px[0], 128, 1) << a;
    EXPECT_NEAR(px[1], 128, 1) << a;
    EXPECT_EQ(px[2], 255) << a;
  }
}

TEST(Warp, TiltedNormalTurnsWithTheFrame) {
  for (double a : {0.0, kPi / 2, 0.7, -2.2}) {
    uint8_t px[3];
    warp_normal(0.6, 0, 0.8, a, px);
    // In the new frame T' = (cos a, sin a, 0), B' = N x T' = (-sin a, cos a, 0).
    EXPECT_NEAR(px[0], enc(0.6 * std::cos(a)), 2) << a;
    EXPECT_NEAR(px[1], enc(-0.6 * std::sin(a)), 2) << a;
    EXPECT_NEAR(px[2], enc(0.8), 2) << a;
  }
}

TEST(Warp, NormalMapKeepsTheObjectSpaceNormalUnderAPatchTurn) {
  // A plane (normal +z) with the usual glTF UVs; the new layout turns the
  // patch by theta. Frames come from corner_tangents on the old and new UVs.
  TriMesh mesh;
  const int n = 4;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.positions.insert(mesh.positions.end(), {float(i) / n, float(j) / n, 0.0f});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
  const OIIO::ImageBuf src =
      make_image(8, 8, 3, [&](int, int, uint8_t* p) { p[0] = enc(0.6), p[1] = enc(0.0), p[2] = enc(0.8); });
  for (double theta : {0.0, 0.4, kPi / 2, 2.5, -1.0}) {
    std::vector<float> old_uv, new_uv, normals;
    for (uint32_t v : mesh.indices) {
      const double x = mesh.positions[3 * v], y = mesh.positions[3 * v + 1];
      old_uv.insert(old_uv.end(), {float(0.1 + 0.8 * x), float(0.1 + 0.8 * (1 - y))});
      const double px = (x - 0.5) * 20, py = -(y - 0.5) * 20;
      new_uv.insert(new_uv.end(), {float((16 + std::cos(theta) * px - std::sin(theta) * py) / 32),
                                   float((16 + std::sin(theta) * px + std::cos(theta) * py) / 32)});
      normals.insert(normals.end(), {0, 0, 1});
    }
    const std::vector<float> old_t = corner_tangents(mesh, normals, old_uv);
    const std::vector<float> new_t = corner_tangents(mesh, normals, new_uv);
    WarpPrimitive p;
    p.source_uv = old_uv;
    p.atlas_uv = new_uv;
    p.normals = normals;
    p.old_tangents = old_t;
    p.new_tangents = new_t;
    const WarpPrimitive prims[1] = {p};
    WarpOptions opt;
    opt.encoding = SlotEncoding::normal;
    OIIO::ImageBuf out;
    ASSERT_EQ(warp_texture(src, prims, 32, 32, opt, out), WarpStatus::ok);
    const uint8_t* px = texel(out, 16, 16);
    const double nx = px[0] / 255.0 * 2 - 1, ny = px[1] / 255.0 * 2 - 1, nz = px[2] / 255.0 * 2 - 1;
    // Object space through the new frame: T, B = w * (N x T), N.
    const double tx = new_t[0], ty = new_t[1], w = new_t[3];
    const double bx = -w * ty, by = w * tx;
    EXPECT_NEAR(nx * tx + ny * bx, 0.6, 0.02) << theta;
    EXPECT_NEAR(nx * ty + ny * by, 0.0, 0.02) << theta;
    EXPECT_NEAR(nz, 0.8, 0.02) << theta;
  }
}

TEST(Warp, BadInput) {
  const OIIO::ImageBuf src = make_image(4, 4, 3, [](int, int, uint8_t* p) { p[0] = p[1] = p[2] = 0; });
  Patch patch;
  patch.add(0, 0, 8, 0, 0, 8, 0, 0, 1, 0, 0, 1, 8, 8, 1);
  WarpPrimitive p = patch.view();
  p.source_uv = p.source_uv.subspan(2);
  const WarpPrimitive prims[1] = {p};
  OIIO::ImageBuf out;
  EXPECT_EQ(warp_texture(src, prims, 8, 8, WarpOptions{}, out), WarpStatus::bad_input);
  const WarpPrimitive ok[1] = {patch.view()};
  WarpOptions opt;
  opt.encoding = SlotEncoding::normal;  // frames missing
  EXPECT_EQ(warp_texture(src, ok, 8, 8, opt, out), WarpStatus::bad_input);
  EXPECT_EQ(warp_texture(OIIO::ImageBuf(), ok, 8, 8, WarpOptions{}, out), WarpStatus::bad_input);
}

// One staging serves many warps (an atlas's pages, its density rounds):
// each page comes out the same as when it staged the source itself, two
// pages read one file, and a staging made for other options is refused.
TEST(Warp, SharedStagingGivesTheSamePages) {
  const int S = 64;
  const OIIO::ImageBuf src = make_image(S, S, 3, [](int x, int y, uint8_t* p) {
    p[0] = uint8_t(x * 4), p[1] = uint8_t(y * 4), p[2] = uint8_t(((x / 8 + y / 8) & 1) ? 230 : 20);
  });
  Patch left, right;
  left.add(4, 4, 40, 0, 0, 56, 0, 0, 0.5, 0, 0, 1, 64, 64);
  right.add(10, 2, 48, 6, -6, 48, 0.5, 0, 0.5, 0, 0, 1, 64, 64);
  WarpOptions opt;  // sRGB, cubic magnification: the staging keeps linear texels
  std::string why;
  const std::shared_ptr<const StagedSource> staged = stage_source(src, opt, why);
  ASSERT_TRUE(staged) << why;
  ASSERT_FALSE(staged->linear.empty());
  ASSERT_TRUE(std::filesystem::exists(staged->path));
  for (const Patch* patch : {&left, &right}) {
    const WarpPrimitive prims[1] = {patch->view()};
    OIIO::ImageBuf alone, shared;
    ASSERT_EQ(warp_texture(src, prims, 64, 64, opt, alone), WarpStatus::ok);
    ASSERT_EQ(warp_texture(src, prims, 64, 64, opt, shared, nullptr, staged.get()), WarpStatus::ok);
    ASSERT_EQ(alone.spec().image_bytes(), shared.spec().image_bytes());
    EXPECT_EQ(std::memcmp(alone.localpixels(), shared.localpixels(), alone.spec().image_bytes()), 0);
  }
  const WarpPrimitive prims[1] = {left.view()};
  OIIO::ImageBuf out;
  WarpOptions linear = opt;
  linear.encoding = SlotEncoding::linear;  // staged in sRGB-decoded values: not this slot's
  EXPECT_EQ(warp_texture(src, prims, 64, 64, linear, out, nullptr, staged.get()), WarpStatus::bad_input);
  const OIIO::ImageBuf other = make_image(32, 32, 3, [](int, int, uint8_t* p) { p[0] = p[1] = p[2] = 9; });
  EXPECT_EQ(warp_texture(other, prims, 64, 64, opt, out, nullptr, staged.get()), WarpStatus::bad_input);
  // The staged file goes with its last owner.
  std::string path;
  {
    const std::shared_ptr<const StagedSource> once = stage_source(src, opt, why);
    ASSERT_TRUE(once) << why;
    path = once->path;
    EXPECT_TRUE(std::filesystem::exists(path));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace gltfwarp
