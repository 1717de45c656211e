// Exact-sign 2D predicates and the small computational-geometry kit that the
// embedding (overlap rejection) and the packer (patch orientation) share.
//
// Sources: orientation by a floating filter with an exact fallback in the
// style of Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
// Robust Geometric Predicates" (1997); convex hull by Andrew's monotone chain
// (1979); minimum-area enclosing rectangle by rotating calipers (Freeman &
// Shapira 1975, Toussaint 1983: one side of the optimal rectangle is collinear
// with a hull edge).
#pragma once

#include <span>
#include <vector>

namespace gltfwarp {

struct Vec2 {
  double x = 0, y = 0;
};

// Exact sign of the signed area of (a, b, c): > 0 counter-clockwise, < 0
// clockwise, 0 collinear. Exact for all finite inputs whose pairwise products
// neither overflow nor underflow (i.e. |coordinates| within ~1e-150..1e150).
int orient2d_sign(Vec2 a, Vec2 b, Vec2 c);

// Plain determinant (b - a) x (c - a): twice the signed area, rounded.
double orient2d(Vec2 a, Vec2 b, Vec2 c);

// True when the open segments ab and cd cross at a single interior point of
// both. Touching at an endpoint, and collinear overlap, are not proper.
bool segments_intersect_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

// True when the interiors of the two triangles intersect (exact). Triangles
// that only share an edge or a vertex, or that merely touch, do not overlap;
// a zero-area triangle has an empty interior and overlaps nothing. Either
// winding is accepted.
bool triangles_overlap(const Vec2 a[3], const Vec2 b[3]);

// Convex hull, counter-clockwise, without collinear points, starting at the
// lowest-x (then lowest-y) point. Fewer than 3 distinct points give those
// points (0, 1 or 2 of them); all-collinear input gives its 2 extreme points.
std::vector<Vec2> convex_hull(std::span<const Vec2> points);

// The minimum-area rectangle enclosing a convex polygon.
//
// Rotation convention: the rectangle's first side (length `width`) points along
// the unit direction u = (cos(angle), sin(angle)); its second side (length
// `height`) along v = (-sin(angle), cos(angle)). Rotating every point by
// -angle, i.e. p' = (p.x*cos(angle) + p.y*sin(angle), -p.x*sin(angle) +
// p.y*cos(angle)) = (dot(p,u), dot(p,v)), makes the rectangle axis-aligned:
// it is then [min_u, min_u + width] x [min_v, min_v + height].
// angle is in (-pi, pi]. width >= height is NOT enforced (the side along the
// chosen hull edge is `width`). For < 3 points: 0 or 1 point gives all zero;
// 2 points give angle along the segment, width = its length, height = 0.
struct OrientedRect {
  double angle = 0;   // radians, see above
  double width = 0;   // extent along u
  double height = 0;  // extent along v
  double area = 0;    // width * height
  double min_u = 0;   // min of dot(p, u) over the hull
  double min_v = 0;   // min of dot(p, v) over the hull
};
OrientedRect min_area_rect(std::span<const Vec2> hull);

}  // namespace gltfwarp
