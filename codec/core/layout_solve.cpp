// The solve layout method (layout_solve.h has the normative steps). Tutte's
// barycentric embedding with a convex boundary (W. T. Tutte, "How to draw a
// graph", 1963; M. S. Floater, "One-to-one piecewise linear mappings over
// triangulations", 2003) followed by local-global ARAP (O. Sorkine and
// M. Alexa, "As-rigid-as-possible surface modeling", 2007; L. Liu et al.,
// "A Local/Global Approach to Mesh Parameterization", 2008). Linear solves
// are plain conjugate gradients (Hestenes & Stiefel, 1952) with a fixed step
// count, so the cost is known before decoding and no residual test decides.
//
// Every sum is accumulated from 0 in the order the comments state; the
// Python and JavaScript decoders repeat these loops operation for operation.
#include "codec/core/layout_solve.h"

#include <algorithm>
#include <cmath>

#include "codec/core/layout.h"

namespace gltfwarp {
namespace {

constexpr uint32_t kNo = 0xFFFFFFFFu;

struct Graph {
  uint32_t n = 0;
  const uint32_t* nbr_off;
  const uint32_t* nbr;
  const double* weight;
  const double* diag;
  const uint8_t* fixed;
};

// (A v)_i for a free row i: d_i v_i - sum over free neighbours j, ascending, of w_ij v_j.
inline double apply_row(const Graph& g, uint32_t i, const double* v) {
  double s = 0;
  for (uint32_t e = g.nbr_off[i]; e < g.nbr_off[i + 1]; ++e) {
    const uint32_t j = g.nbr[e];
    if (!g.fixed[j]) s += g.weight[e] * v[j];
  }
  return g.diag[i] * v[i] - s;
}

// Conjugate gradients on the free rows, both coordinates side by side (each
// with its own scalars), `steps` steps from the current x, y. bx, by hold the
// right-hand side of the free rows.
void conjugate_gradients(const Graph& g, const double* bx, const double* by, double* x, double* y,
                         uint32_t steps, SolveScratch& s) {
  const uint32_t n = g.n;
  s.r.assign(2 * size_t{n}, 0.0);
  s.p.assign(2 * size_t{n}, 0.0);
  s.q.assign(2 * size_t{n}, 0.0);
  double* rx = s.r.data();
  double* ry = rx + n;
  double* px = s.p.data();
  double* py = px + n;
  double* qx = s.q.data();
  double* qy = qx + n;
  double rrx = 0, rry = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (g.fixed[i]) continue;
    rx[i] = bx[i] - apply_row(g, i, x);
    ry[i] = by[i] - apply_row(g, i, y);
    px[i] = rx[i];
    py[i] = ry[i];
    rrx += rx[i] * rx[i];
    rry += ry[i] * ry[i];
  }
  for (uint32_t step = 0; step < steps; ++step) {
    double pqx = 0, pqy = 0;
    for (uint32_t i = 0; i < n; ++i) {
      if (g.fixed[i]) continue;
      qx[i] = apply_row(g, i, px);
      qy[i] = apply_row(g, i, py);
      pqx += px[i] * qx[i];
      pqy += py[i] * qy[i];
    }
    const double ax = rrx / (pqx + kSolveTiny), ay = rry / (pqy + kSolveTiny);
    double nx = 0, ny = 0;
    for (uint32_t i = 0; i < n; ++i) {
      if (g.fixed[i]) continue;
      x[i] = x[i] + ax * px[i];
      y[i] = y[i] + ay * py[i];
      rx[i] = rx[i] - ax * qx[i];
      ry[i] = ry[i] - ay * qy[i];
      nx += rx[i] * rx[i];
      ny += ry[i] * ry[i];
    }
    const double bx_ = nx / (rrx + kSolveTiny), by_ = ny / (rry + kSolveTiny);
    for (uint32_t i = 0; i < n; ++i) {
      if (g.fixed[i]) continue;
      px[i] = rx[i] + bx_ * px[i];
      py[i] = ry[i] + by_ * py[i];
    }
    rrx = nx;
    rry = ny;
  }
}

// b_i = c_i + sum over fixed neighbours j, ascending, of w_ij x_j (free rows).
void add_fixed_terms(const Graph& g, const double* x, const double* y, double* bx, double* by) {
  for (uint32_t i = 0; i < g.n; ++i) {
    if (g.fixed[i]) continue;
    double fx = 0, fy = 0;
    for (uint32_t e = g.nbr_off[i]; e < g.nbr_off[i + 1]; ++e) {
      const uint32_t j = g.nbr[e];
      if (!g.fixed[j]) continue;
      fx += g.weight[e] * x[j];
      fy += g.weight[e] * y[j];
    }
    bx[i] = bx[i] + fx;
    by[i] = by[i] + fy;
  }
}

// Cotangent weights (step 4, cotangent_weights): face t's edge (t_k,
// t_k+1) gets w_t[k] from the corner opposite it in its isometric copy;
// w[i][j] is the sum over the (at most two) faces holding the edge, and
// d[i] the sum of row i in ascending neighbour order.
void cotangent_laplacian(std::span<const uint32_t> faces, const uint32_t* idx, SolveScratch& s, uint32_t n) {
  const size_t nf = faces.size();
  s.face_weight.resize(3 * nf);
  std::fill(s.weight.begin(), s.weight.end(), 0.0);
  auto entry = [&](uint32_t a, uint32_t b) {
    return std::lower_bound(s.nbr.begin() + s.nbr_off[a], s.nbr.begin() + s.nbr_off[a + 1], b) -
           s.nbr.begin();
  };
  for (size_t t = 0; t < nf; ++t) {
    const uint32_t* tri = idx + 3 * size_t{faces[t]};
    const double* X = &s.frame[6 * t];
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      const double w = solve_cotangent_weight(X[2 * k] - X[2 * k2], X[2 * k + 1] - X[2 * k2 + 1],
                                              X[2 * k1] - X[2 * k2], X[2 * k1 + 1] - X[2 * k2 + 1]);
      s.face_weight[3 * t + k] = w;
      const uint32_t i = s.local[tri[k]], j = s.local[tri[k1]];
      s.weight[entry(i, j)] += w;
      s.weight[entry(j, i)] += w;
    }
  }
  for (uint32_t i = 0; i < n; ++i) {
    double d = 0;
    for (uint32_t e = s.nbr_off[i]; e < s.nbr_off[i + 1]; ++e) d += s.weight[e];
    s.diag[i] = d;
  }
}

}  // namespace

double solve_cotangent_weight(double ax, double ay, double bx, double by) {
  const double c = (ax * bx + ay * by) / (std::fabs(ax * by - ay * bx) + kSolveTiny);
  return c < kSolveMinCot ? kSolveMinCot : (c > kSolveMaxCot ? kSolveMaxCot : c);
}

Vec2 solve_circle_point(double u, double r) {
  // tan(pi u / 4) by its [3/2] Pade approximant, then the rational point of
  // angle 2 atan(t) = pi u / 2, doubled twice: angle ~ 2 pi u.
  const double a = 0.7853981633974483 * u;
  const double a2 = a * a;
  const double t = a * (15.0 - a2) / (15.0 - 6.0 * a2);
  const double t2 = t * t;
  const double c1 = (1.0 - t2) / (1.0 + t2), s1 = (2.0 * t) / (1.0 + t2);
  const double c2 = c1 * c1 - s1 * s1, s2 = (2.0 * c1) * s1;
  const double c = c2 * c2 - s2 * s2, s = (2.0 * c2) * s2;
  return {r * (c - 1.0), r * s};
}

SolveStatus solve_patch(const TriMesh& mesh, std::span<const uint32_t> faces, const SolveParams& params,
                        std::vector<Vec2>& pos, SolveScratch& s) {
  const uint32_t* idx = mesh.indices.data();
  const size_t nf = faces.size();
  // ---- local numbering: the patch's vertices in ascending id.
  s.verts.clear();
  for (const uint32_t f : faces)
    for (int k = 0; k < 3; ++k) s.verts.push_back(idx[3 * size_t{f} + k]);
  std::sort(s.verts.begin(), s.verts.end());
  s.verts.erase(std::unique(s.verts.begin(), s.verts.end()), s.verts.end());
  const uint32_t n = static_cast<uint32_t>(s.verts.size());
  if (s.local.size() < mesh.vertex_count()) s.local.resize(mesh.vertex_count());
  for (uint32_t i = 0; i < n; ++i) s.local[s.verts[i]] = i;
  auto lv = [&](uint32_t f, int k) { return s.local[idx[3 * size_t{f} + k]]; };

  // ---- validation: oriented, edge-manifold disc.
  s.out_off.assign(size_t{n} + 1, 0);
  for (const uint32_t f : faces) {
    const uint32_t a = lv(f, 0), b = lv(f, 1), c = lv(f, 2);
    if (a == b || b == c || a == c) return SolveStatus::not_disc;
    ++s.out_off[a + 1], ++s.out_off[b + 1], ++s.out_off[c + 1];
  }
  for (uint32_t i = 0; i < n; ++i) s.out_off[i + 1] += s.out_off[i];
  s.out_to.resize(3 * nf);
  {
    std::vector<uint32_t>& fill = s.queue;
    fill.assign(s.out_off.begin(), s.out_off.end() - 1);
    for (const uint32_t f : faces)
      for (int k = 0; k < 3; ++k) s.out_to[fill[lv(f, k)]++] = lv(f, (k + 1) % 3);
  }
  for (uint32_t i = 0; i < n; ++i) {
    const auto b = s.out_to.begin() + s.out_off[i], e = s.out_to.begin() + s.out_off[i + 1];
    std::sort(b, e);
    if (std::adjacent_find(b, e) != e) return SolveStatus::not_disc;  // a directed edge twice
  }
  auto has_edge = [&](uint32_t a, uint32_t b) {
    return std::binary_search(s.out_to.begin() + s.out_off[a], s.out_to.begin() + s.out_off[a + 1], b);
  };
  s.bout.assign(n, kNo);
  uint32_t boundary = 0;
  for (uint32_t a = 0; a < n; ++a)
    for (uint32_t e = s.out_off[a]; e < s.out_off[a + 1]; ++e) {
      const uint32_t b = s.out_to[e];
      if (has_edge(b, a)) continue;
      if (s.bout[a] != kNo) return SolveStatus::not_disc;
      s.bout[a] = b;
      ++boundary;
    }
  if (boundary < 3) return SolveStatus::not_disc;
  uint32_t start = 0;
  while (s.bout[start] == kNo) ++start;
  s.loop.clear();
  for (uint32_t v = start; s.loop.size() <= boundary;) {
    s.loop.push_back(v);
    v = s.bout[v];
    if (v == kNo) return SolveStatus::not_disc;
    if (v == start) break;
  }
  if (s.loop.size() != boundary) return SolveStatus::not_disc;
  if (2 * int64_t{n} - int64_t(nf) - int64_t{boundary} != 2) return SolveStatus::not_disc;

  // ---- the Laplacian: neighbours ascending, weight = faces holding the edge.
  s.nbr_off.assign(size_t{n} + 1, 0);
  for (uint32_t a = 0; a < n; ++a)
    for (uint32_t e = s.out_off[a]; e < s.out_off[a + 1]; ++e)
      ++s.nbr_off[a + 1], ++s.nbr_off[s.out_to[e] + 1];
  for (uint32_t i = 0; i < n; ++i) s.nbr_off[i + 1] += s.nbr_off[i];
  s.nbr.resize(s.nbr_off[n]);
  {
    std::vector<uint32_t>& fill = s.queue;
    fill.assign(s.nbr_off.begin(), s.nbr_off.end() - 1);
    for (uint32_t a = 0; a < n; ++a)
      for (uint32_t e = s.out_off[a]; e < s.out_off[a + 1]; ++e) {
        const uint32_t b = s.out_to[e];
        s.nbr[fill[a]++] = b;
        s.nbr[fill[b]++] = a;
      }
  }
  // Compress each row to distinct neighbours with their multiplicity.
  s.weight.resize(s.nbr.size());
  s.diag.assign(n, 0.0);
  {
    uint32_t w = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t b = s.nbr_off[i], e = s.nbr_off[i + 1];
      std::sort(s.nbr.begin() + b, s.nbr.begin() + e);
      s.nbr_off[i] = w;
      uint32_t deg = 0;
      for (uint32_t k = b; k < e; ++k) {
        if (k > b && s.nbr[k] == s.nbr[k - 1]) {
          s.weight[w - 1] += 1.0;
        } else {
          s.nbr[w] = s.nbr[k];
          s.weight[w++] = 1.0;
        }
        ++deg;
      }
      s.diag[i] = static_cast<double>(deg);
    }
    s.nbr_off[n] = w;
  }
  // Every vertex reaches the loop.
  s.seen.assign(n, 0);
  s.queue.clear();
  s.queue.push_back(start);
  s.seen[start] = 1;
  for (size_t h = 0; h < s.queue.size(); ++h) {
    const uint32_t a = s.queue[h];
    for (uint32_t e = s.nbr_off[a]; e < s.nbr_off[a + 1]; ++e)
      if (!s.seen[s.nbr[e]]) s.seen[s.nbr[e]] = 1, s.queue.push_back(s.nbr[e]);
  }
  if (s.queue.size() != n) return SolveStatus::not_disc;

  // ---- boundary on the circle, by cumulative 3D arc length.
  s.x.assign(n, 0.0);
  s.y.assign(n, 0.0);
  double* x = s.x.data();
  double* y = s.y.data();
  {
    double total = 0;
    s.r.resize(boundary);  // arc length at each loop vertex
    for (uint32_t i = 0; i < boundary; ++i) {
      s.r[i] = total;
      const uint32_t a = s.verts[s.loop[i]], b = s.verts[s.loop[(i + 1) % boundary]];
      total += std::sqrt(length3_sq(mesh, a, b));
    }
    const double radius = total / 6.283185307179586;
    for (uint32_t i = 0; i < boundary; ++i) {
      const Vec2 q = solve_circle_point(s.r[i] / (total + kSolveTiny), radius);
      x[s.loop[i]] = q.x;
      y[s.loop[i]] = q.y;
    }
  }
  s.fixed.assign(n, 0);
  for (const uint32_t v : s.loop) s.fixed[v] = 1;
  Graph g{n, s.nbr_off.data(), s.nbr.data(), s.weight.data(), s.diag.data(), s.fixed.data()};

  // ---- Tutte: interior rows, right-hand side from the boundary.
  s.bx.assign(n, 0.0);
  s.by.assign(n, 0.0);
  add_fixed_terms(g, x, y, s.bx.data(), s.by.data());
  conjugate_gradients(g, s.bx.data(), s.by.data(), x, y, params.tutte_iterations, s);

  // ---- each face's isometric copy: X0 = (0, 0), X1 = (|e1|, 0),
  // X2 = (e1.e2, |e1 x e2|) / |e1|, with e1 = P1 - P0, e2 = P2 - P0.
  s.frame.resize(6 * nf);
  const float* P = mesh.positions.data();
  for (size_t t = 0; t < nf; ++t) {
    const uint32_t* tri = idx + 3 * size_t{faces[t]};
    double e1[3], e2[3];
    for (int c = 0; c < 3; ++c) {
      e1[c] = double(P[3 * size_t{tri[1]} + c]) - double(P[3 * size_t{tri[0]} + c]);
      e2[c] = double(P[3 * size_t{tri[2]} + c]) - double(P[3 * size_t{tri[0]} + c]);
    }
    const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    const double dot = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    const double cx = e1[1] * e2[2] - e1[2] * e2[1];
    const double cy = e1[2] * e2[0] - e1[0] * e2[2];
    const double cz = e1[0] * e2[1] - e1[1] * e2[0];
    const double cross = std::sqrt(cx * cx + cy * cy + cz * cz);
    double* X = &s.frame[6 * t];
    X[0] = 0.0, X[1] = 0.0, X[2] = l1, X[3] = 0.0;
    X[4] = dot / (l1 + kSolveTiny), X[5] = cross / (l1 + kSolveTiny);
  }

  // ---- ARAP: the loop start stays pinned at the origin. Each face edge's
  // weight is 1 (the Laplacian stays Tutte's) or its clamped cotangent.
  if (params.cotangent_weights)
    cotangent_laplacian(faces, idx, s, n);
  else
    s.face_weight.assign(3 * nf, 1.0);
  std::fill(s.fixed.begin(), s.fixed.end(), 0);
  s.fixed[start] = 1;
  s.rot.resize(2 * nf);
  for (uint32_t round = 0; round < params.arap_iterations; ++round) {
    for (size_t t = 0; t < nf; ++t) {  // local step
      const uint32_t* tri = idx + 3 * size_t{faces[t]};
      const double* X = &s.frame[6 * t];
      double a = 0, b = 0, c = 0, d = 0;
      for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        const uint32_t i = s.local[tri[k]], j = s.local[tri[k1]];
        const double w = s.face_weight[3 * t + k];
        const double ux = w * (x[j] - x[i]), uy = w * (y[j] - y[i]);
        const double vx = X[2 * k1] - X[2 * k], vy = X[2 * k1 + 1] - X[2 * k + 1];
        a += ux * vx;
        b += ux * vy;
        c += uy * vx;
        d += uy * vy;
      }
      const double pc = a + d, ps = c - b;
      const double len = std::sqrt(pc * pc + ps * ps);
      s.rot[2 * t] = pc / (len + kSolveTiny);
      s.rot[2 * t + 1] = ps / (len + kSolveTiny);
    }
    std::fill(s.bx.begin(), s.bx.end(), 0.0);  // global step's right-hand side
    std::fill(s.by.begin(), s.by.end(), 0.0);
    for (size_t t = 0; t < nf; ++t) {
      const uint32_t* tri = idx + 3 * size_t{faces[t]};
      const double* X = &s.frame[6 * t];
      const double co = s.rot[2 * t], si = s.rot[2 * t + 1];
      for (int k = 0; k < 3; ++k)
        for (int m = 1; m <= 2; ++m) {
          const int j = (k + m) % 3;
          const uint32_t i = s.local[tri[k]];
          // Edge (k, k+1) is face edge k; edge (k+2, k) is face edge k+2 = j.
          const double w = s.face_weight[3 * t + (m == 1 ? k : j)];
          const double ex = w * (X[2 * k] - X[2 * j]), ey = w * (X[2 * k + 1] - X[2 * j + 1]);
          s.bx[i] += co * ex - si * ey;
          s.by[i] += si * ex + co * ey;
        }
    }
    add_fixed_terms(g, x, y, s.bx.data(), s.by.data());
    conjugate_gradients(g, s.bx.data(), s.by.data(), x, y, params.arap_cg_iterations, s);
  }

  // ---- similarity scale: 3D over 2D edge length sums, over the faces' edges.
  double l3 = 0, l2 = 0;
  for (size_t t = 0; t < nf; ++t) {
    const uint32_t* tri = idx + 3 * size_t{faces[t]};
    for (int k = 0; k < 3; ++k) {
      const uint32_t va = tri[k], vb = tri[(k + 1) % 3];
      l3 += std::sqrt(length3_sq(mesh, va, vb));
      const double dx = x[s.local[vb]] - x[s.local[va]], dy = y[s.local[vb]] - y[s.local[va]];
      l2 += std::sqrt(dx * dx + dy * dy);
    }
  }
  const double scale = l3 / (l2 + kSolveTiny);
  for (uint32_t i = 0; i < n; ++i) pos[s.verts[i]] = {scale * x[i], scale * y[i]};
  return SolveStatus::ok;
}

}  // namespace gltfwarp
