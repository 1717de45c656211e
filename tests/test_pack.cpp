// Packing: no overlap, patches inside the page, gutters kept, fill, sizes.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <random>

#include "codec/encode/atlas/pack.h"
#include "codec/encode/atlas/texel_density.h"

namespace gltfwarp {
namespace {

// A set of generated patches: star-shaped blobs (ragged), rectangles, strips.
struct GenPrim {
  TriMesh mesh;
  std::vector<uint32_t> patch_of_face;
  std::vector<double> corner_xy;
  uint32_t patch_count = 0;
  PackPrimitive view() const {
    return PackPrimitive{&mesh, patch_of_face, patch_count, corner_xy, {}, {}, {}, {}, {}, {}, {}, {}};
  }
};

void add_tri(GenPrim& g, uint32_t patch, double ax, double ay, double bx, double by, double cx, double cy) {
  const double xy[6] = {ax, ay, bx, by, cx, cy};
  for (int v = 0; v < 3; ++v) {
    g.mesh.indices.push_back(g.mesh.vertex_count());
    g.mesh.positions.insert(g.mesh.positions.end(), {float(xy[2 * v]), float(xy[2 * v + 1]), 0.0f});
    g.corner_xy.push_back(xy[2 * v]);
    g.corner_xy.push_back(xy[2 * v + 1]);
  }
  g.patch_of_face.push_back(patch);
}

GenPrim generate(uint32_t patches, uint32_t seed, double size = 10.0, bool lshapes = false) {
  GenPrim g;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (uint32_t p = 0; p < patches; ++p) {
    const double cx = u(rng) * 100, cy = u(rng) * 100, rot = u(rng) * 6.28;
    const double sz = size * (0.3 + 1.4 * u(rng));
    const int kind = int(rng() % (lshapes ? 4 : 3));
    auto tr = [&](double x, double y, double& ox, double& oy) {
      ox = cx + std::cos(rot) * x - std::sin(rot) * y;
      oy = cy + std::sin(rot) * x + std::cos(rot) * y;
    };
    if (kind == 0) {  // star blob, fan-triangulated
      const int n = 12;
      double rad[n];
      for (int k = 0; k < n; ++k) rad[k] = sz * (0.5 + 0.5 * u(rng));
      for (int k = 0; k < n; ++k) {
        const double a0 = 6.2831853 * k / n, a1 = 6.2831853 * (k + 1) / n;
        double x0, y0, x1, y1, x2, y2;
        tr(0, 0, x0, y0);
        tr(rad[k] * std::cos(a0), rad[k] * std::sin(a0), x1, y1);
        tr(rad[(k + 1) % n] * std::cos(a1), rad[(k + 1) % n] * std::sin(a1), x2, y2);
        add_tri(g, p, x0, y0, x1, y1, x2, y2);
      }
    } else if (kind == 3) {  // L shape: two arms of a square of side sz
      const double t = sz * 0.3;
      const double quads[2][4] = {{0, 0, sz, t}, {0, t, t, sz}};
      for (const auto& qd : quads) {
        double x[4], y[4];
        tr(qd[0], qd[1], x[0], y[0]);
        tr(qd[2], qd[1], x[1], y[1]);
        tr(qd[2], qd[3], x[2], y[2]);
        tr(qd[0], qd[3], x[3], y[3]);
        add_tri(g, p, x[0], y[0], x[1], y[1], x[2], y[2]);
        add_tri(g, p, x[0], y[0], x[2], y[2], x[3], y[3]);
      }
    } else {  // rectangle grid (kind 1) or thin strip (kind 2)
      const double w = sz * (kind == 2 ? 3.0 : 1.0), h = sz * (kind == 2 ? 0.25 : 0.7);
      const int nx = 4, ny = 2;
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          double x[4], y[4];
          tr(w * i / nx, h * j / ny, x[0], y[0]);
          tr(w * (i + 1) / nx, h * j / ny, x[1], y[1]);
          tr(w * (i + 1) / nx, h * (j + 1) / ny, x[2], y[2]);
          tr(w * i / nx, h * (j + 1) / ny, x[3], y[3]);
          add_tri(g, p, x[0], y[0], x[1], y[1], x[2], y[2]);
          add_tri(g, p, x[0], y[0], x[2], y[2], x[3], y[3]);
        }
    }
  }
  g.patch_count = patches;
  return g;
}

// Conservative footprint of every patch at its final placement; checks that
// no texel belongs to two patches, every footprint is inside its page, and
// different patches stay `gutter` empty texels apart.
void check_footprints(std::span<const PackPrimitive> prims, const PackResult& res, uint32_t gutter) {
  const uint32_t w = res.report.atlas_width, h = res.report.atlas_height;
  for (uint32_t page = 0; page < res.report.page_count; ++page) {
    std::vector<int32_t> owner(size_t(w) * h, -1);
    int32_t base = 0;
    uint64_t inside_fail = 0, shared = 0;
    for (size_t i = 0; i < prims.size(); ++i) {
      std::vector<double> t;
      placed_corner_texels(prims[i].corner_xy, res.maps[i], t);
      for (size_t f = 0; f < res.maps[i].patch_of_face.size(); ++f) {
        const uint32_t patch = res.maps[i].patch_of_face[f];
        if (res.maps[i].placements[patch].page != page) continue;
        double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
        for (int v = 0; v < 3; ++v) {
          x0 = std::min(x0, t[6 * f + 2 * v]), x1 = std::max(x1, t[6 * f + 2 * v]);
          y0 = std::min(y0, t[6 * f + 2 * v + 1]), y1 = std::max(y1, t[6 * f + 2 * v + 1]);
        }
        // bounding-box texels are a superset of the triangle's footprint only
        // for small triangles; use the texels the triangle's centre-fan touches
        for (long long j = (long long)std::floor(y0); j <= (long long)std::floor(y1); ++j)
          for (long long i2 = (long long)std::floor(x0); i2 <= (long long)std::floor(x1); ++i2) {
            // square [i2, i2+1] x [j, j+1] against the triangle: sample 5x5 points
            bool hit = false;
            const double* p = &t[6 * f];
            double area = (p[2] - p[0]) * (p[5] - p[1]) - (p[3] - p[1]) * (p[4] - p[0]);
            for (int sy = 0; sy <= 4 && !hit; ++sy)
              for (int sx = 0; sx <= 4 && !hit; ++sx) {
                const double x = i2 + sx / 4.0, y = j + sy / 4.0;
                double e0 = (p[2] - p[0]) * (y - p[1]) - (p[3] - p[1]) * (x - p[0]);
                double e1 = (p[4] - p[2]) * (y - p[3]) - (p[5] - p[3]) * (x - p[2]);
                double e2 = (p[0] - p[4]) * (y - p[5]) - (p[1] - p[5]) * (x - p[4]);
                if (area < 0) e0 = -e0, e1 = -e1, e2 = -e2;
                hit = e0 >= 0 && e1 >= 0 && e2 >= 0;
              }
            if (!hit) continue;
            if (i2 < 0 || j < 0 || i2 >= (long long)w || j >= (long long)h) {
              ++inside_fail;
              continue;
            }
            int32_t& o = owner[size_t(j) * w + size_t(i2)];
            if (o >= 0 && o != base + int32_t(patch)) ++shared;
            o = base + int32_t(patch);
          }
      }
      base += int32_t(res.maps[i].patch_count);
    }
    EXPECT_EQ(inside_fail, 0u) << "page " << page;
    EXPECT_EQ(shared, 0u) << "page " << page;
    uint64_t near = 0;
    const int g = int(gutter);
    for (int j = 0; j < int(h); ++j)
      for (int i = 0; i < int(w); ++i) {
        const int32_t o = owner[size_t(j) * w + i];
        if (o < 0) continue;
        for (int dj = -g; dj <= g; ++dj)
          for (int di = -g; di <= g; ++di) {
            const int x = i + di, y = j + dj;
            if (x < 0 || y < 0 || x >= int(w) || y >= int(h)) continue;
            const int32_t o2 = owner[size_t(y) * w + x];
            if (o2 >= 0 && o2 != o) ++near;
          }
      }
    EXPECT_EQ(near, 0u) << "texels of different patches closer than the gutter, page " << page;
  }
}

TEST(Pack, NoOverlapGutterInsideAndFill) {
  const GenPrim a = generate(60, 1), b = generate(40, 2, 6.0);
  const PackPrimitive prims[2] = {a.view(), b.view()};
  PackOptions opt;
  opt.texel_scale = 4.0;
  opt.gutter = 4;
  PackResult res;
  ASSERT_EQ(pack_atlas(prims, opt, res), PackStatus::ok);
  const PackReport& r = res.report;
  EXPECT_EQ(r.overlap_texels, 0u);
  EXPECT_EQ(r.outside_texels, 0u);
  EXPECT_EQ(r.patch_count, 100u);
  EXPECT_EQ(r.atlas_width % 16, 0u);  // MIP levels 0..4 halve exactly
  EXPECT_EQ(r.atlas_height % 16, 0u);
  EXPECT_EQ(r.page_count, 1u);
  ASSERT_EQ(res.maps.size(), 2u);
  EXPECT_EQ(res.maps[1].placements.size(), 40u);
  check_footprints(prims, res, opt.gutter);
  std::printf("fill %.3f atlas %ux%u covered %llu, %.1f ms\n", r.fill, r.atlas_width, r.atlas_height,
              (unsigned long long)r.covered_texels, r.seconds * 1e3);
  EXPECT_GT(r.fill, 0.6);
}

// The source's texel axes, as seen in the atlas: per face, the angle (in
// degrees, folded into [-45, 45)) of the source u gradient over the placed
// corners. 0 means the source's columns run along the atlas's.
std::vector<double> source_axis_angles(const GenPrim& g, std::span<const float> source_uv, const UvMap& map) {
  std::vector<double> t, out;
  placed_corner_texels(g.corner_xy, map, t);
  for (size_t f = 0; f < g.patch_of_face.size(); ++f) {
    const double* c = &t[6 * f];
    const float* uv = &source_uv[6 * f];
    const double e1x = c[2] - c[0], e1y = c[3] - c[1], e2x = c[4] - c[0], e2y = c[5] - c[1];
    const double det = e1x * e2y - e1y * e2x;
    const double d1 = double(uv[2]) - uv[0], d2 = double(uv[4]) - uv[0];
    const double gx = (d1 * e2y - d2 * e1y) / det, gy = (d2 * e1x - d1 * e2x) / det;
    double a = std::atan2(gy, gx) * 180 / 3.14159265358979 + 45;
    a = a - 90 * std::floor(a / 90) - 45;
    out.push_back(a);
  }
  return out;
}

TEST(Pack, SourceAxesRunAlongTheAtlas) {
  // Each patch's source UVs: its layout turned by its own angle (mirrored for
  // every third patch) and scaled, as a source atlas holds a chart.
  const GenPrim g = generate(40, 5);
  std::vector<float> source_uv(g.corner_xy.size());
  std::mt19937 rng(9);
  std::vector<double> turn(g.patch_count);
  for (double& a : turn) a = std::uniform_real_distribution<double>(0, 6.2831853)(rng);
  for (size_t f = 0; f < g.patch_of_face.size(); ++f) {
    const uint32_t p = g.patch_of_face[f];
    const double c = std::cos(turn[p]), s = std::sin(turn[p]), m = p % 3 == 0 ? -1.0 : 1.0;
    for (int v = 0; v < 3; ++v) {
      const double x = g.corner_xy[6 * f + 2 * v], y = m * g.corner_xy[6 * f + 2 * v + 1];
      source_uv[6 * f + 2 * v] = float(0.01 * (c * x - s * y));
      source_uv[6 * f + 2 * v + 1] = float(0.01 * (s * x + c * y));
    }
  }
  PackPrimitive prim = g.view();
  prim.source_uv = source_uv;
  PackOptions opt;
  opt.texel_scale = 4.0;
  double worst[2] = {0, 0};
  for (PatchOrientation o : {PatchOrientation::source_axes, PatchOrientation::min_rectangle}) {
    opt.orientation = o;
    PackResult res;
    ASSERT_EQ(pack_atlas({&prim, 1}, opt, res), PackStatus::ok);
    EXPECT_EQ(res.report.overlap_texels, 0u);
    for (double a : source_axis_angles(g, source_uv, res.maps[0]))
      worst[o == PatchOrientation::min_rectangle] =
          std::max(worst[o == PatchOrientation::min_rectangle], std::abs(a));
  }
  // Within half a rotation code (360 / 256 / 2 degrees) plus rounding.
  EXPECT_LE(worst[0], 0.71);
  EXPECT_GT(worst[1], 5.0);  // the rectangle rule ignores the source, so the check can fail
}

TEST(Pack, TrueShapesBeatRectanglesAndSkyline) {
  const GenPrim a = generate(120, 7, 10.0, true);
  const PackPrimitive prims[1] = {a.view()};
  PackOptions opt;
  opt.texel_scale = 4.0;
  PackResult shapes, rects, sky;
  ASSERT_EQ(pack_atlas(prims, opt, shapes), PackStatus::ok);
  opt.method = PackMethod::skyline;
  ASSERT_EQ(pack_atlas(prims, opt, sky), PackStatus::ok);
  opt.method = PackMethod::bitmap;
  opt.true_shapes = false;
  ASSERT_EQ(pack_atlas(prims, opt, rects), PackStatus::ok);
  for (const PackResult* r : {&shapes, &rects, &sky}) {
    EXPECT_EQ(r->report.overlap_texels, 0u);
    EXPECT_EQ(r->report.outside_texels, 0u);
    check_footprints(prims, *r, opt.gutter);
  }
  std::printf("fill: true shapes %.3f, skyline %.3f, rectangles %.3f\n", shapes.report.fill, sky.report.fill,
              rects.report.fill);
  EXPECT_GT(shapes.report.fill, rects.report.fill + 0.04);
  EXPECT_GT(shapes.report.fill, sky.report.fill);
}

TEST(Pack, PowerOfTwoAndShrinkToMaxSize) {
  const GenPrim a = generate(50, 3);
  const PackPrimitive prims[1] = {a.view()};
  PackOptions opt;
  opt.texel_scale = 50.0;  // far too large for 512
  opt.max_atlas_size = 512;
  opt.rounding = SizeRounding::power_of_two;
  PackResult res;
  ASSERT_EQ(pack_atlas(prims, opt, res), PackStatus::ok);
  const PackReport& r = res.report;
  EXPECT_LE(r.atlas_width, 512u);
  EXPECT_LE(r.atlas_height, 512u);
  EXPECT_EQ(r.atlas_width & (r.atlas_width - 1), 0u);
  EXPECT_EQ(r.atlas_height & (r.atlas_height - 1), 0u);
  EXPECT_LT(r.texel_scale, 50.0);
  EXPECT_GT(r.shrink_retries, 0u);
  EXPECT_FLOAT_EQ(res.maps[0].texel_scale, float(r.texel_scale));
  EXPECT_EQ(r.overlap_texels, 0u);
  EXPECT_EQ(r.outside_texels, 0u);
  check_footprints(prims, res, opt.gutter);
}

// A --max-atlas-size that is no multiple of 16 bounds the page as asked: a
// height that fits it is never rounded past it (the trial would fail, and
// the patches would shrink for nothing), so over a range of densities some
// page uses the rows between 288 and 300; every side stays within 300 and is
// a multiple of 16 or the bound itself.
TEST(Pack, MaxSizeNoMultipleOf16StaysTheBound) {
  const GenPrim a = generate(50, 3);
  const PackPrimitive prims[1] = {a.view()};
  int tall = 0;
  for (int k = 0; k < 24; ++k) {
    PackOptions opt;
    opt.texel_scale = 8.0 * std::pow(1.08, k);
    opt.max_atlas_size = 300;
    PackResult res;
    ASSERT_EQ(pack_atlas(prims, opt, res), PackStatus::ok);
    const PackReport& r = res.report;
    EXPECT_LE(r.atlas_width, 300u);
    EXPECT_LE(r.atlas_height, 300u);
    EXPECT_TRUE(r.atlas_width % 16 == 0 || r.atlas_width == 300u) << r.atlas_width;
    EXPECT_TRUE(r.atlas_height % 16 == 0 || r.atlas_height == 300u) << r.atlas_height;
    EXPECT_EQ(r.overlap_texels, 0u);
    EXPECT_EQ(r.outside_texels, 0u);
    tall += r.atlas_height > 288u;
  }
  EXPECT_GT(tall, 0) << "no page used the rows past the last multiple of 16 below the bound";
}

TEST(Pack, SeveralPages) {
  const GenPrim a = generate(80, 4);
  const PackPrimitive prims[1] = {a.view()};
  PackOptions opt;
  opt.texel_scale = 6.0;
  opt.max_atlas_size = 512;
  opt.max_pages = 8;
  PackResult res;
  ASSERT_EQ(pack_atlas(prims, opt, res), PackStatus::ok);
  EXPECT_GT(res.report.page_count, 1u);
  EXPECT_EQ(res.report.shrink_retries, 0u);
  EXPECT_EQ(res.maps[0].page_count, res.report.page_count);
  EXPECT_EQ(res.report.overlap_texels, 0u);
  EXPECT_EQ(res.report.outside_texels, 0u);
  check_footprints(prims, res, opt.gutter);
}

TEST(TexelDensity, MeasuresTexelsPerUnit) {
  // Two unit right triangles (a unit square) mapped to half of a 512 x 256
  // image: 256 x 256 texels per unit square, i.e. 256 texels per unit.
  TriMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 0, 0, 7, 0, 0, 7, 2, 0};
  m.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6};
  const std::vector<float> uv = {0, 0, 0.5f, 0, 0.5f, 1, 0, 0, 0.5f, 1, 0, 1,
                                 // third face: 2 x 2 units on 64 x 64 texels: 32 per unit
                                 0, 0, 0.125f, 0, 0.125f, 0.25f};
  const std::vector<double> d = triangle_texel_density(m, uv, 512, 256);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_NEAR(d[0], 256, 1e-3);
  EXPECT_NEAR(d[1], 256, 1e-3);
  EXPECT_NEAR(d[2], 32, 1e-3);
  const DensityPrimitive p{&m, uv, 512, 256};
  // Default budget: the distinct texels used (the third face reuses texels of
  // the first two): 65536 over 1 + 2 units of area.
  TexelDensityReport r = auto_texel_scale({&p, 1});
  EXPECT_NEAR(r.used_texels, 65536, 300);
  EXPECT_NEAR(r.texel_scale, std::sqrt(65536.0 / 3.0), 0.5);
  EXPECT_NEAR(r.max_density, 256, 1e-3);
  TexelDensityOptions o;
  o.mode = DensityMode::preserve_texel_count;  // every use counts: 65536 + 2048 texels
  EXPECT_NEAR(auto_texel_scale({&p, 1}, o).texel_scale, std::sqrt((65536.0 + 2048.0) / 3.0), 1e-6);
  o.mode = DensityMode::percentile;
  o.percentile = 0.9;
  EXPECT_NEAR(auto_texel_scale({&p, 1}, o).texel_scale, 256, 1e-3);
  o.percentile = 0.5;  // the 2-unit face holds 2/3 of the area
  EXPECT_NEAR(auto_texel_scale({&p, 1}, o).texel_scale, 32, 1e-3);
}

TEST(TexelDensity, ScaleFollowsTheModelsUnits) {
  // The same textured square in units from 1e-20 to 1e30: the atlas must get
  // the same texels, so the scale (texels per unit) goes as 1 / unit. An
  // absolute floor of 1e-9 texels per unit once made the 1e30 square 4096².
  const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
  for (const float unit : {1e-20f, 1.0f, 1e6f, 1e30f}) {
    SCOPED_TRACE(unit);
    TriMesh m;
    m.positions = {0, 0, 0, unit, 0, 0, unit, unit, 0, 0, unit, 0};
    m.indices = {0, 1, 2, 0, 2, 3};
    const DensityPrimitive p{&m, uv, 64, 64};
    EXPECT_NEAR(auto_texel_scale({&p, 1}).texel_scale * unit, 64, 1);
  }
}

TEST(Pack, PerPatchScaleKeepsEachPatchsDensity) {
  const GenPrim a = generate(40, 8);
  // Source density: 8 texels per unit on even patches, 2 on odd ones.
  std::vector<double> density(a.patch_of_face.size());
  for (size_t f = 0; f < density.size(); ++f) density[f] = a.patch_of_face[f] % 2 ? 2.0 : 8.0;
  PackPrimitive prim = a.view();
  prim.face_density = density;
  PackOptions opt;
  opt.texel_scale = 4.0;
  PackResult res;
  ASSERT_EQ(pack_atlas({&prim, 1}, opt, res), PackStatus::ok);
  EXPECT_EQ(res.report.overlap_texels, 0u);
  EXPECT_EQ(res.report.outside_texels, 0u);
  // Relative to the set's RMS density: the 8s get 2^(s/4) ~ 8 / rms, the 2s
  // four steps (a factor 4 in density) less.
  int32_t even = res.maps[0].placements[0].scale_step, odd = res.maps[0].placements[1].scale_step;
  EXPECT_GT(even, 0);
  EXPECT_LT(odd, 0);
  EXPECT_EQ(even - odd, 8);
  for (uint32_t p = 0; p < 40; ++p) EXPECT_EQ(res.maps[0].placements[p].scale_step, p % 2 ? odd : even) << p;
  check_footprints({&prim, 1}, res, opt.gutter);
  PackResult flat;
  opt.per_patch_scale = false;
  ASSERT_EQ(pack_atlas({&prim, 1}, opt, flat), PackStatus::ok);
  for (const PatchPlacement& pl : flat.maps[0].placements) EXPECT_EQ(pl.scale_step, 0);
}

TEST(Pack, BadInput) {
  GenPrim a = generate(3, 5);
  a.patch_of_face[0] = 7;
  const PackPrimitive prims[1] = {a.view()};
  PackOptions opt;
  opt.texel_scale = 1.0;
  PackResult res;
  EXPECT_EQ(pack_atlas(prims, opt, res), PackStatus::bad_input);
  opt.texel_scale = 0;
  a.patch_of_face[0] = 0;
  EXPECT_EQ(pack_atlas(prims, opt, res), PackStatus::bad_input);
}

// Stopping trials that cannot win changes only the time: the same page
// size and the same placement for every patch, with both methods, one
// page and several, over sets where many trials lose.
TEST(Pack, StoppingLosingTrialsKeepsThePacking) {
  uint32_t stops = 0;
  for (const uint32_t seed : {3u, 11u, 29u}) {
    const GenPrim a = generate(150, seed, 10.0, true);
    const PackPrimitive prims[1] = {a.view()};
    for (const PackMethod method : {PackMethod::bitmap, PackMethod::skyline})
      for (const uint32_t max_pages : {1u, 3u}) {
        SCOPED_TRACE(testing::Message()
                     << "seed " << seed << " method " << int(method) << " pages " << max_pages);
        PackOptions opt;
        opt.texel_scale = 4.0;
        opt.method = method;
        opt.max_pages = max_pages;
        if (max_pages > 1) opt.max_atlas_size = 512;  // spills into pages
        PackResult stopped, full;
        ASSERT_EQ(pack_atlas(prims, opt, stopped), PackStatus::ok);
        opt.stop_losing_trials = false;
        ASSERT_EQ(pack_atlas(prims, opt, full), PackStatus::ok);
        EXPECT_EQ(full.report.stopped_trials, 0u);
        stops += stopped.report.stopped_trials;
        EXPECT_EQ(stopped.report.atlas_width, full.report.atlas_width);
        EXPECT_EQ(stopped.report.atlas_height, full.report.atlas_height);
        EXPECT_EQ(stopped.report.page_count, full.report.page_count);
        EXPECT_EQ(stopped.report.texel_scale, full.report.texel_scale);
        ASSERT_EQ(stopped.maps.size(), full.maps.size());
        const std::vector<PatchPlacement>& ps = stopped.maps[0].placements;
        const std::vector<PatchPlacement>& pf = full.maps[0].placements;
        ASSERT_EQ(ps.size(), pf.size());
        for (size_t i = 0; i < ps.size(); ++i) {
          EXPECT_EQ(ps[i].x, pf[i].x) << "patch " << i;
          EXPECT_EQ(ps[i].y, pf[i].y) << "patch " << i;
          EXPECT_EQ(ps[i].page, pf[i].page) << "patch " << i;
          EXPECT_EQ(ps[i].rotation, pf[i].rotation) << "patch " << i;
        }
      }
  }
  std::printf("trials stopped early: %u\n", stops);
  EXPECT_GT(stops, 0u) << "no trial stopped: the comparison above tested nothing";
}

// Speed is measured in benchmarks/bench_warp.cpp, never asserted here.
TEST(Pack, ThousandsOfPatchesPackWithoutOverlap) {
  const GenPrim a = generate(3000, 6, 3.0);
  const PackPrimitive prims[1] = {a.view()};
  PackOptions opt;
  opt.texel_scale = 6.0;
  PackResult res;
  ASSERT_EQ(pack_atlas(prims, opt, res), PackStatus::ok);
  EXPECT_EQ(res.report.overlap_texels, 0u);
  EXPECT_EQ(res.report.outside_texels, 0u);
  EXPECT_EQ(res.report.patch_count, 3000u);
}

}  // namespace
}  // namespace gltfwarp

// layout_texel_density: geometric mean of the largest singular value and
// sqrt|det| of the layout -> source texel map.
TEST(TexelDensity, LayoutDensityMixesLargestStretchAndAreaScale) {
  // Layout: a right triangle with unit legs. Source: 4x along x, 1x along y
  // (in a 100 x 100 image, UV = texels / 100): sigma_max 4, sqrt|det| 2.
  const std::vector<double> xy = {0, 0, 1, 0, 0, 1};
  const std::vector<float> uv = {0.1f, 0.1f, 0.14f, 0.1f, 0.1f, 0.11f};
  const std::vector<double> s = gltfwarp::layout_texel_density(xy, uv, 100, 100);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0], std::sqrt(8.0), 1e-4);
  // Rotating the layout does not change it; a degenerate layout gives 0.
  const double c = std::cos(0.7), n = std::sin(0.7);
  const std::vector<double> rot = {0, 0, c, n, -n, c};
  EXPECT_NEAR(gltfwarp::layout_texel_density(rot, uv, 100, 100)[0], std::sqrt(8.0), 1e-4);
  EXPECT_EQ(gltfwarp::layout_texel_density(std::vector<double>{0, 0, 1, 1, 2, 2}, uv, 100, 100)[0], 0.0);
}
