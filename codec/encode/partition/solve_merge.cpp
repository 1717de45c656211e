// Solve merges (solve_merge.h): most shared edges first, like the unfold
// merges of embed.cpp, but each trial is laid out by the decoder's
// solve_patch and judged on exactly those positions.
#include "codec/encode/partition/solve_merge.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "codec/core/distortion.h"
#include "codec/core/geometry2d.h"
#include "codec/core/layout.h"
#include "codec/core/layout_report.h"
#include "codec/core/topology.h"
#include "codec/encode/partition/patch_pairs.h"

namespace gltfwarp {
namespace {

// Closed segments ab and cd share a point (proper crossing, or an endpoint
// on the other segment). Exact.
bool segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  if (segments_intersect_properly(a, b, c, d)) return true;
  auto on = [](Vec2 p, Vec2 q, Vec2 x) {
    return orient2d_sign(p, q, x) == 0 && std::min(p.x, q.x) <= x.x && x.x <= std::max(p.x, q.x) &&
           std::min(p.y, q.y) <= x.y && x.y <= std::max(p.y, q.y);
  };
  return on(a, b, c) || on(a, b, d) || on(c, d, a) || on(c, d, b);
}

}  // namespace

bool solved_patch_acceptable(const TriMesh& mesh, std::span<const uint32_t> faces, std::span<const double> xy,
                             double tau) {
  const uint32_t* idx = mesh.indices.data();
  double area = 0;
  // Directed edges with their 2D ends; the boundary is those without reverse.
  struct Edge {
    uint32_t a, b;
    Vec2 pa, pb;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * faces.size());
  for (const uint32_t f : faces) {
    const double* c = &xy[6 * size_t{f}];
    const Vec2 P[3] = {{c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]}};
    if (orient2d_sign(P[0], P[1], P[2]) <= 0) return false;
    if (!(face_distortion(mesh, f, P) <= tau)) return false;
    area += orient2d(P[0], P[1], P[2]);
    for (int k = 0; k < 3; ++k)
      edges.push_back({idx[3 * f + k], idx[3 * f + (k + 1) % 3], P[k], P[(k + 1) % 3]});
  }
  std::sort(edges.begin(), edges.end(),
            [](const Edge& l, const Edge& r) { return l.a != r.a ? l.a < r.a : l.b < r.b; });
  auto has = [&](uint32_t a, uint32_t b) {
    return std::binary_search(
        edges.begin(), edges.end(), Edge{a, b, {}, {}},
        [](const Edge& l, const Edge& r) { return l.a != r.a ? l.a < r.a : l.b < r.b; });
  };
  std::vector<Edge> loop;
  for (const Edge& e : edges)
    if (!has(e.b, e.a)) loop.push_back(e);
  // Area enclosed by the boundary (shoelace, twice the area) must equal the
  // faces' area: a wrapped interior vertex covers some region twice.
  double enclosed = 0;
  for (const Edge& e : loop) enclosed += e.pa.x * e.pb.y - e.pb.x * e.pa.y;
  if (!(std::fabs(enclosed - area) <= 1e-9 * area)) return false;
  // A simple boundary: no two edges meet except consecutive ones at their shared end.
  std::sort(loop.begin(), loop.end(),
            [](const Edge& l, const Edge& r) { return std::min(l.pa.x, l.pb.x) < std::min(r.pa.x, r.pb.x); });
  for (size_t i = 0; i < loop.size(); ++i) {
    const double hi = std::max(loop[i].pa.x, loop[i].pb.x);
    for (size_t j = i + 1; j < loop.size() && std::min(loop[j].pa.x, loop[j].pb.x) <= hi; ++j) {
      const Edge &e = loop[i], &o = loop[j];
      const bool adjacent = e.b == o.a || o.b == e.a;
      if (adjacent) {
        // Consecutive edges meet at their common vertex only: not collinear back over each other.
        const Vec2 shared = e.b == o.a ? e.pb : e.pa;
        const Vec2 x = e.b == o.a ? e.pa : e.pb, y = e.b == o.a ? o.pb : o.pa;
        if (orient2d_sign(x, shared, y) == 0 &&
            (x.x - shared.x) * (y.x - shared.x) + (x.y - shared.y) * (y.y - shared.y) > 0)
          return false;
        continue;
      }
      if (segments_meet(e.pa, e.pb, o.pa, o.pb)) return false;
    }
  }
  return true;
}

size_t solve_merge(const TriMesh& mesh, std::span<const uint32_t> opp,
                   std::vector<std::vector<uint32_t>>& patches, std::vector<double>& xy,
                   std::vector<uint8_t>& method, const SolveMergeOptions& opt,
                   const std::function<bool(uint32_t, uint32_t)>& can_join) {
  const uint32_t nf = mesh.face_count();
  const uint32_t np = static_cast<uint32_t>(patches.size());
  method.resize(np, uint8_t(LayoutMethod::unfold));
  std::vector<uint32_t> patch_of(nf, kNone);
  for (uint32_t p = 0; p < np; ++p)
    for (uint32_t f : patches[p]) patch_of[f] = p;
  std::vector<double> fill(np, 1.0);
  std::vector<Vec2> scratch;
  for (uint32_t p = 0; p < np; ++p) fill[p] = patch_fill(patches[p], xy, scratch);
  std::vector<uint32_t> version(np, 0), touched(np, 0), unite;
  std::set<std::array<uint32_t, 4>> failed;
  double budget = opt.budget * double(nf) + 65536.0;
  double solved_faces = 0;
  const double max_solved = opt.max_solved_share * double(nf);
  std::vector<Vec2> pos(mesh.vertex_count());
  std::vector<double> saved;
  SolveScratch ss;
  size_t merges = 0;
  std::vector<uint64_t> keys;
  std::vector<PatchPair> pairs;
  for (int round = 1; round <= opt.rounds; ++round) {
    adjacent_patch_pairs(opp, patch_of, keys, pairs);
    bool merged_any = false;
    for (const PatchPair& pr : pairs) {
      if (touched[pr.a] == uint32_t(round) || touched[pr.b] == uint32_t(round)) continue;
      std::vector<uint32_t>& A = patches[pr.a];
      std::vector<uint32_t>& B = patches[pr.b];
      const size_t n = A.size() + B.size();
      if (n > opt.max_faces) continue;
      const double newly = double(method[pr.a] ? 0 : A.size()) + double(method[pr.b] ? 0 : B.size());
      if (solved_faces + newly > max_solved) continue;
      const std::array<uint32_t, 4> memo = {pr.a, version[pr.a], pr.b, version[pr.b]};
      if (failed.count(memo)) continue;
      if (!can_join(pr.a, pr.b)) continue;
      if (budget < double(n)) return merges;
      budget -= double(n);
      unite.assign(A.begin(), A.end());
      unite.insert(unite.end(), B.begin(), B.end());
      std::sort(unite.begin(), unite.end());
      bool ok = solve_patch(mesh, unite, opt.params, pos, ss) == SolveStatus::ok;
      if (ok) {
        saved.resize(6 * n);
        for (size_t i = 0; i < n; ++i) {
          const uint32_t f = unite[i];
          std::copy_n(&xy[6 * size_t{f}], 6, &saved[6 * i]);
          for (int k = 0; k < 3; ++k) {
            const Vec2 q = pos[mesh.indices[3 * size_t{f} + k]];
            xy[6 * size_t{f} + 2 * k] = q.x;
            xy[6 * size_t{f} + 2 * k + 1] = q.y;
          }
        }
        ok = solved_patch_acceptable(mesh, unite, xy, opt.tau);
        double fu = 0;
        if (ok) {
          fu = patch_fill(unite, xy, scratch);
          ok = fu >= std::min(opt.min_fill, std::min(fill[pr.a], fill[pr.b]));
        }
        if (ok) {
          fill[pr.a] = fu;
        } else {
          for (size_t i = 0; i < n; ++i) std::copy_n(&saved[6 * i], 6, &xy[6 * size_t{unite[i]}]);
        }
      }
      if (!ok) {
        failed.insert(memo);
        continue;
      }
      touched[pr.a] = touched[pr.b] = uint32_t(round);
      solved_faces += newly;
      for (uint32_t f : B) patch_of[f] = pr.a;
      A = unite;
      B.clear();
      method[pr.a] = uint8_t(LayoutMethod::solve);
      method[pr.b] = uint8_t(LayoutMethod::unfold);
      ++version[pr.a];
      ++merges;
      merged_any = true;
    }
    if (!merged_any) break;
  }
  return merges;
}

}  // namespace gltfwarp
