// Exact predicates, hull and min-area rectangle (codec/core/geometry2d.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codec/core/geometry2d.h"

namespace gltfwarp {
namespace {

TEST(Geometry2d, OrientSignIsExactNearCollinear) {
  // Points on the line y = x, shifted by one ulp: the naive determinant
  // rounds, the exact sign must not.
  const Vec2 a{0.5, 0.5}, b{12.0, 12.0};
  for (int k = 0; k < 200; ++k) {
    const double x = 24.0 + k * 1e-3;
    const Vec2 on{x, x};
    EXPECT_EQ(orient2d_sign(a, b, on), 0);
    const Vec2 above{x, std::nextafter(x, 1e9)};
    const Vec2 below{x, std::nextafter(x, -1e9)};
    EXPECT_EQ(orient2d_sign(a, b, above), 1);
    EXPECT_EQ(orient2d_sign(a, b, below), -1);
    EXPECT_EQ(orient2d_sign(b, a, above), -1);
  }
}

TEST(Geometry2d, SegmentsProper) {
  EXPECT_TRUE(segments_intersect_properly({0, 0}, {2, 2}, {0, 2}, {2, 0}));
  EXPECT_FALSE(segments_intersect_properly({0, 0}, {2, 2}, {2, 2}, {3, 0}));  // endpoint touch
  EXPECT_FALSE(segments_intersect_properly({0, 0}, {2, 0}, {1, 0}, {3, 0}));  // collinear
  EXPECT_FALSE(segments_intersect_properly({0, 0}, {1, 1}, {0, 2}, {2, 3}));
}

TEST(Geometry2d, TrianglesOverlap) {
  const Vec2 t[3] = {{0, 0}, {1, 0}, {0, 1}};
  const Vec2 shared_edge[3] = {{1, 0}, {0, 1}, {1, 1}};
  const Vec2 shared_vertex[3] = {{1, 0}, {2, 0}, {2, 1}};
  const Vec2 crossing[3] = {{0.2, 0.2}, {2, 0.2}, {0.2, 2}};
  const Vec2 inside[3] = {{0.1, 0.1}, {0.2, 0.1}, {0.1, 0.2}};
  const Vec2 cw_same[3] = {{0, 0}, {0, 1}, {1, 0}};
  const Vec2 degenerate[3] = {{0, 0}, {1, 1}, {2, 2}};
  const Vec2 folded[3] = {{1, 0}, {0, 1}, {0.4, 0.4}};  // flipped across shared edge
  EXPECT_FALSE(triangles_overlap(t, shared_edge));
  EXPECT_FALSE(triangles_overlap(t, shared_vertex));
  EXPECT_TRUE(triangles_overlap(t, crossing));
  EXPECT_TRUE(triangles_overlap(t, inside));
  EXPECT_TRUE(triangles_overlap(inside, t));
  EXPECT_TRUE(triangles_overlap(t, cw_same));
  EXPECT_FALSE(triangles_overlap(t, degenerate));
  EXPECT_TRUE(triangles_overlap(t, folded));
}

TEST(Geometry2d, HullAndRect) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-1, 1);
  const double ang = 0.3;
  const double c = std::cos(ang), s = std::sin(ang);
  std::vector<Vec2> pts;
  for (int i = 0; i < 500; ++i) {
    const double x = 3 * d(rng), y = d(rng);  // in a 6 x 2 box rotated by ang
    pts.push_back({x * c - y * s, x * s + y * c});
  }
  for (Vec2 corner : {Vec2{-3, -1}, Vec2{3, -1}, Vec2{3, 1}, Vec2{-3, 1}})
    pts.push_back({corner.x * c - corner.y * s, corner.x * s + corner.y * c});
  const std::vector<Vec2> hull = convex_hull(pts);
  ASSERT_EQ(hull.size(), 4u);
  for (size_t i = 0; i < hull.size(); ++i)
    EXPECT_GT(orient2d_sign(hull[i], hull[(i + 1) % 4], hull[(i + 2) % 4]), 0);
  const OrientedRect r = min_area_rect(hull);
  EXPECT_NEAR(r.area, 12.0, 1e-9);
  // Rotating by -angle must make the rectangle axis-aligned and contain all.
  const double rc = std::cos(r.angle), rs = std::sin(r.angle);
  for (Vec2 p : pts) {
    const double u = p.x * rc + p.y * rs, v = -p.x * rs + p.y * rc;
    EXPECT_GE(u, r.min_u - 1e-9);
    EXPECT_LE(u, r.min_u + r.width + 1e-9);
    EXPECT_GE(v, r.min_v - 1e-9);
    EXPECT_LE(v, r.min_v + r.height + 1e-9);
  }
  EXPECT_TRUE(std::fabs(std::remainder(r.angle - ang, M_PI / 2)) < 1e-9);
}

TEST(Geometry2d, HullSmallInputs) {
  EXPECT_TRUE(convex_hull(std::vector<Vec2>{}).empty());
  EXPECT_EQ(convex_hull(std::vector<Vec2>{{1, 1}, {1, 1}}).size(), 1u);
  EXPECT_EQ(convex_hull(std::vector<Vec2>{{0, 0}, {1, 1}, {2, 2}, {3, 3}}).size(), 2u);
  const std::vector<Vec2> seg = {{0, 0}, {3, 4}};
  const OrientedRect r = min_area_rect(seg);
  EXPECT_DOUBLE_EQ(r.width, 5.0);
  EXPECT_EQ(r.area, 0.0);
}

}  // namespace
}  // namespace gltfwarp
