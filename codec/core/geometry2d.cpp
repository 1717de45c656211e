// Robust 2D predicates, convex hull and minimum-area rectangle.
// Sources: Shewchuk 1997 (exact expansions: Two-Sum, Two-Product via
// Dekker/Veltkamp splitting); Andrew 1979 (monotone chain hull); Freeman &
// Shapira 1975 and Toussaint 1983 (rotating calipers, min-area rectangle).
#include "codec/core/geometry2d.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gltfwarp {
namespace {

// Error-free transforms (Shewchuk 1997, section 2). Require round-to-nearest
// and no FMA contraction, which the build guarantees (-ffp-contract=off).
inline void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bv = s - a;
  const double av = s - bv;
  e = (a - av) + (b - bv);
}

inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  const double abig = c - a;
  hi = c - abig;
  lo = a - hi;
}

inline void two_product(double a, double b, double& p, double& e) {
  p = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  e = ((ahi * bhi - p) + ahi * blo + alo * bhi) + alo * blo;
}

// Exact sign of sum_i terms[i] (an expansion built by repeated two_sum).
int exact_sign_of_sum(const double* terms, int n) {
  // Grow-expansion: keep a nonoverlapping expansion h[0..m), smallest first.
  double h[32];
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double q = terms[i];
    int k = 0;
    for (int j = 0; j < m; ++j) {
      double s, e;
      two_sum(q, h[j], s, e);
      q = s;
      if (e != 0) h[k++] = e;
    }
    if (q != 0) h[k++] = q;
    m = k;
  }
  if (m == 0) return 0;
  // The largest-magnitude component is last and carries the sign.
  return h[m - 1] > 0 ? 1 : (h[m - 1] < 0 ? -1 : 0);
}

int orient2d_exact(Vec2 a, Vec2 b, Vec2 c) {
  // (a-c) x (b-c) expanded into six products of input coordinates:
  // ax*by - ax*cy - cx*by - ay*bx + ay*cx + cy*bx.
  double t[12];
  two_product(a.x, b.y, t[0], t[1]);
  two_product(-a.x, c.y, t[2], t[3]);
  two_product(-c.x, b.y, t[4], t[5]);
  two_product(-a.y, b.x, t[6], t[7]);
  two_product(a.y, c.x, t[8], t[9]);
  two_product(c.y, b.x, t[10], t[11]);
  return exact_sign_of_sum(t, 12);
}

}  // namespace

double orient2d(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

int orient2d_sign(Vec2 a, Vec2 b, Vec2 c) {
  // Shewchuk's orient2d filter: the signs of the two rounded products are
  // exact (a rounded difference keeps its sign), so when they differ, or one
  // is zero, the sign of their difference is exact too. Only otherwise is the
  // error bound (ccwerrboundA) needed, and past it the exact expansion.
  const double detleft = (a.x - c.x) * (b.y - c.y);
  const double detright = (a.y - c.y) * (b.x - c.x);
  const double det = detleft - detright;
  double detsum;
  if (detleft > 0) {
    if (detright <= 0) return det > 0 ? 1 : (det < 0 ? -1 : 0);
    detsum = detleft + detright;
  } else if (detleft < 0) {
    if (detright >= 0) return det > 0 ? 1 : (det < 0 ? -1 : 0);
    detsum = -detleft - detright;
  } else {
    return detright < 0 ? 1 : (detright > 0 ? -1 : 0);
  }
  const double errbound = 3.3306690738754716e-16 * detsum;  // (3 + 16 eps) eps
  if (det > errbound) return 1;
  if (-det > errbound) return -1;
  return orient2d_exact(a, b, c);
}

bool segments_intersect_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orient2d_sign(a, b, c), o2 = orient2d_sign(a, b, d);
  if (o1 == 0 || o2 == 0 || o1 == o2) return false;
  const int o3 = orient2d_sign(c, d, a), o4 = orient2d_sign(c, d, b);
  return o3 != 0 && o4 != 0 && o3 != o4;
}

bool triangles_overlap(const Vec2 a[3], const Vec2 b[3]) {
  // Separating-axis theorem for convex polygons with closed half-planes: the
  // interiors are disjoint iff some edge line of either triangle has the
  // other triangle entirely on its closed outer side.
  const int sa = orient2d_sign(a[0], a[1], a[2]);
  const int sb = orient2d_sign(b[0], b[1], b[2]);
  if (sa == 0 || sb == 0) return false;  // empty interior
  for (int pass = 0; pass < 2; ++pass) {
    const Vec2* p = pass == 0 ? a : b;
    const Vec2* q = pass == 0 ? b : a;
    const int s = pass == 0 ? sa : sb;
    for (int i = 0; i < 3; ++i) {
      const Vec2 e0 = p[i], e1 = p[(i + 1) % 3];
      bool some_inside = false;
      for (int j = 0; j < 3 && !some_inside; ++j) some_inside = orient2d_sign(e0, e1, q[j]) * s > 0;
      if (!some_inside) return false;  // separated by this edge's line
    }
  }
  return true;
}

std::vector<Vec2> convex_hull(std::span<const Vec2> points) {
  std::vector<Vec2> p(points.begin(), points.end());
  std::sort(p.begin(), p.end(), [](Vec2 l, Vec2 r) { return l.x < r.x || (l.x == r.x && l.y < r.y); });
  p.erase(std::unique(p.begin(), p.end(), [](Vec2 l, Vec2 r) { return l.x == r.x && l.y == r.y; }), p.end());
  if (p.size() < 3) return p;
  std::vector<Vec2> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && orient2d_sign(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {  // upper chain
    while (k >= t && orient2d_sign(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);  // the last point repeats the first
  return h;
}

OrientedRect min_area_rect(std::span<const Vec2> hull) {
  OrientedRect best;
  const size_t n = hull.size();
  if (n < 2) return best;
  if (n == 2) {
    const double dx = hull[1].x - hull[0].x, dy = hull[1].y - hull[0].y;
    const double len = std::sqrt(dx * dx + dy * dy);
    best.angle = std::atan2(dy, dx);
    best.width = len;
    if (len > 0) {
      const double ux = dx / len, uy = dy / len;
      best.min_u = std::min(hull[0].x * ux + hull[0].y * uy, hull[1].x * ux + hull[1].y * uy);
      best.min_v = -hull[0].x * uy + hull[0].y * ux;
    }
    return best;
  }
  best.area = std::numeric_limits<double>::infinity();
  auto dot = [](Vec2 p, double ux, double uy) { return p.x * ux + p.y * uy; };
  // Calipers: for edge i with direction u and left normal v (interior side
  // of a ccw hull), track the vertices extreme along +u, +v and -u. Each
  // pointer only advances, so the sweep is O(n).
  size_t jmax_u = 0, jmax_v = 0, jmin_u = 0;
  bool first = true;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p0 = hull[i], p1 = hull[(i + 1) % n];
    const double dx = p1.x - p0.x, dy = p1.y - p0.y;
    const double len = std::sqrt(dx * dx + dy * dy);
    if (len == 0) continue;
    const double ux = dx / len, uy = dy / len, vx = -uy, vy = ux;
    if (first) {
      jmax_u = jmax_v = jmin_u = i;
      first = false;
    }
    jmax_u = std::max(jmax_u, i);  // keep pointers ahead of the edge start
    while (dot(hull[(jmax_u + 1) % n], ux, uy) > dot(hull[jmax_u % n], ux, uy)) ++jmax_u;
    if (jmax_v < jmax_u) jmax_v = jmax_u;
    while (dot(hull[(jmax_v + 1) % n], vx, vy) > dot(hull[jmax_v % n], vx, vy)) ++jmax_v;
    if (jmin_u < jmax_v) jmin_u = jmax_v;
    while (dot(hull[(jmin_u + 1) % n], ux, uy) < dot(hull[jmin_u % n], ux, uy)) ++jmin_u;
    const double u0 = dot(hull[jmin_u % n], ux, uy), u1 = dot(hull[jmax_u % n], ux, uy);
    const double v0 = dot(p0, vx, vy), v1 = dot(hull[jmax_v % n], vx, vy);
    const double w = u1 - u0, h = v1 - v0, area = w * h;
    if (area < best.area) {
      best.area = area;
      best.width = w;
      best.height = h;
      best.angle = std::atan2(uy, ux);
      best.min_u = u0;
      best.min_v = v0;
    }
  }
  if (first) best.area = 0;
  return best;
}

}  // namespace gltfwarp
