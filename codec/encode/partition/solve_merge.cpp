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
#include "codec/encode/partition/notch_moves.h"
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
    if (!face_within_tau(mesh, f, P, tau)) return false;
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

namespace {

// One run of solve merges and seam moves over a partition (solve_merge.h).
class SolveMerger {
 public:
  SolveMerger(const TriMesh& mesh, std::span<const uint32_t> opp, std::vector<std::vector<uint32_t>>& patches,
              std::vector<double>& xy, std::vector<uint8_t>& method, const SolveMergeOptions& opt,
              const JoinRule& can_join)
      : mesh_(mesh), opp_(opp), patches_(patches), xy_(xy), method_(method), opt_(opt), can_join_(can_join) {
    const uint32_t nf = mesh.face_count();
    const uint32_t np = static_cast<uint32_t>(patches.size());
    method_.resize(np, uint8_t(LayoutMethod::unfold));
    patch_of_.assign(nf, kNone);
    for (uint32_t p = 0; p < np; ++p)
      for (uint32_t f : patches[p]) patch_of_[f] = p;
    fill_.assign(np, 1.0);
    for (uint32_t p = 0; p < np; ++p) fill_[p] = patch_fill(patches[p], xy, scratch_);
    version_.assign(np, 0);
    touched_.assign(np, 0);
    budget_ = opt.budget * double(nf) + 65536.0;
    max_solved_ = opt.max_solved_share * double(nf);
    pos_.resize(mesh.vertex_count());
  }

  size_t run() {
    for (int round = 1; round <= opt_.rounds && budget_ > 0; ++round) {
      const size_t before = merges_ + moves_;
      merge_round(uint32_t(2 * round - 1));
      move_round(uint32_t(2 * round));
      if (merges_ + moves_ == before) break;
    }
    return merges_ + moves_;
  }

 private:
  // Unions of adjacent patches, most shared edges first, each patch in at most one per round.
  void merge_round(uint32_t stamp) {
    adjacent_patch_pairs(opp_, patch_of_, keys_, pairs_);
    for (const PatchPair& pr : pairs_) {
      if (touched_[pr.a] == stamp || touched_[pr.b] == stamp) continue;
      std::vector<uint32_t>& A = patches_[pr.a];
      std::vector<uint32_t>& B = patches_[pr.b];
      const size_t n = A.size() + B.size();
      if (n > opt_.max_faces) continue;
      const double newly = unsolved(pr.a) + unsolved(pr.b);
      if (solved_faces_ + newly > max_solved_) continue;
      const std::array<uint32_t, 4> memo = {pr.a, version_[pr.a], pr.b, version_[pr.b]};
      if (failed_merges_.count(memo)) continue;
      if (!can_join_(A, B)) continue;
      if (budget_ < double(n)) return;
      budget_ -= double(n);
      unite_.assign(A.begin(), A.end());
      unite_.insert(unite_.end(), B.begin(), B.end());
      std::sort(unite_.begin(), unite_.end());
      begin_trial();
      double fu = 0;
      const bool ok = lay_out(unite_, std::min(fill_[pr.a], fill_[pr.b]), fu);
      if (!ok) {
        restore();
        failed_merges_.insert(memo);
        continue;
      }
      fill_[pr.a] = fu;
      touched_[pr.a] = touched_[pr.b] = stamp;
      solved_faces_ += newly;
      for (uint32_t f : B) patch_of_[f] = pr.a;
      A = unite_;
      B.clear();
      method_[pr.a] = uint8_t(LayoutMethod::solve);
      method_[pr.b] = uint8_t(LayoutMethod::unfold);
      ++version_[pr.a];
      ++merges_;
    }
  }

  // Seam moves: a face with two or three edges on patch B (a notch or a
  // hole in A's outline) moves to B, one or three seam edges fewer, when
  // both patches still solve within the rules. The faces of one (A, B) pair
  // move as a batch, most faces first. Both patches become solve patches.
  void move_round(uint32_t stamp) {
    notch_moves(opp_, patch_of_, moves_found_, groups_);
    std::vector<uint32_t> moved;
    for (const NotchGroup& gr : groups_) {
      const uint32_t a = moves_found_[gr.begin].a, b = moves_found_[gr.begin].b;
      if (touched_[a] == stamp || touched_[b] == stamp) continue;
      const std::array<uint32_t, 4> memo = {a, version_[a], b, version_[b]};
      if (failed_moves_.count(memo)) continue;
      // The whole batch, else (it may fold or stretch where one face does
      // not) its faces one at a time, up to a few.
      moved.clear();
      for (size_t t = gr.begin; t < gr.end; ++t) moved.push_back(moves_found_[t].f);
      bool done = try_move(a, b, moved, stamp);
      for (size_t t = gr.begin; !done && gr.end - gr.begin > 1 && t < std::min(gr.end, gr.begin + 8); ++t) {
        moved.assign(1, moves_found_[t].f);
        done = try_move(a, b, moved, stamp);
      }
      if (!done) failed_moves_.insert(memo);
      if (budget_ <= 0) return;
    }
  }

  // Moves the faces `moved` (ascending) from patch a to patch b if both then
  // solve within the rules; false (nothing changed) otherwise.
  bool try_move(uint32_t a, uint32_t b, const std::vector<uint32_t>& moved, uint32_t stamp) {
    std::vector<uint32_t>& A = patches_[a];
    std::vector<uint32_t>& B = patches_[b];
    if (moved.size() >= A.size()) return false;  // all of A: a merge, not a move
    if (B.size() + moved.size() > opt_.max_faces || A.size() > opt_.max_faces) return false;
    const double newly = unsolved(a) + unsolved(b);
    if (solved_faces_ + newly > max_solved_) return false;
    if (!can_join_(B, moved)) return false;
    const double n = double(A.size() + B.size());
    if (budget_ < n) {
      budget_ = 0;
      return false;
    }
    budget_ -= n;
    rest_.clear();
    for (uint32_t f : A)
      if (!std::binary_search(moved.begin(), moved.end(), f)) rest_.push_back(f);
    std::sort(rest_.begin(), rest_.end());
    unite_.assign(B.begin(), B.end());
    unite_.insert(unite_.end(), moved.begin(), moved.end());
    std::sort(unite_.begin(), unite_.end());
    begin_trial();
    double fa = 0, fb = 0;
    if (!lay_out(rest_, fill_[a], fa) || !lay_out(unite_, fill_[b], fb)) {
      restore();
      return false;
    }
    for (uint32_t f : moved) patch_of_[f] = b;
    A = rest_;
    B = unite_;
    fill_[a] = fa;
    fill_[b] = fb;
    touched_[a] = touched_[b] = stamp;
    solved_faces_ += newly;
    method_[a] = method_[b] = uint8_t(LayoutMethod::solve);
    ++version_[a];
    ++version_[b];
    moves_ += moved.size();
    return true;
  }

  double unsolved(uint32_t p) const { return method_[p] ? 0.0 : double(patches_[p].size()); }

  // Solves the face set (ascending) as one patch and writes its positions to
  // xy, saving what they replace; true when the decoder's result passes
  // solved_patch_acceptable and keeps a fill of at least min_fill
  // (min(options' floor, the parts')). fill_out: its fill.
  bool lay_out(const std::vector<uint32_t>& faces, double min_fill, double& fill_out) {
    if (solve_patch(mesh_, faces, opt_.params, pos_, ss_) != SolveStatus::ok) return false;
    for (const uint32_t f : faces) {
      saved_faces_.push_back(f);
      const size_t at = saved_.size();
      saved_.resize(at + 6);
      std::copy_n(&xy_[6 * size_t{f}], 6, &saved_[at]);
      for (int k = 0; k < 3; ++k) {
        const Vec2 q = pos_[mesh_.indices[3 * size_t{f} + k]];
        xy_[6 * size_t{f} + 2 * k] = q.x;
        xy_[6 * size_t{f} + 2 * k + 1] = q.y;
      }
    }
    if (!solved_patch_acceptable(mesh_, faces, xy_, opt_.tau)) return false;
    fill_out = patch_fill(faces, xy_, scratch_);
    return fill_out >= std::min(opt_.min_fill, min_fill);
  }

  void begin_trial() {
    saved_faces_.clear();
    saved_.clear();
  }

  // Puts back the positions lay_out replaced since begin_trial (latest first).
  void restore() {
    for (size_t i = saved_faces_.size(); i-- > 0;)
      std::copy_n(&saved_[6 * i], 6, &xy_[6 * size_t{saved_faces_[i]}]);
    begin_trial();
  }

  const TriMesh& mesh_;
  std::span<const uint32_t> opp_;
  std::vector<std::vector<uint32_t>>& patches_;
  std::vector<double>& xy_;
  std::vector<uint8_t>& method_;
  const SolveMergeOptions& opt_;
  const JoinRule& can_join_;
  std::vector<uint32_t> patch_of_, version_, touched_, unite_, rest_, saved_faces_;
  std::vector<double> fill_, saved_;
  std::set<std::array<uint32_t, 4>> failed_merges_, failed_moves_;
  double budget_ = 0, solved_faces_ = 0, max_solved_ = 0;
  size_t merges_ = 0, moves_ = 0;
  std::vector<Vec2> pos_, scratch_;
  SolveScratch ss_;
  std::vector<uint64_t> keys_;
  std::vector<PatchPair> pairs_;
  std::vector<NotchMove> moves_found_;
  std::vector<NotchGroup> groups_;
};

}  // namespace

size_t solve_merge(const TriMesh& mesh, std::span<const uint32_t> opp,
                   std::vector<std::vector<uint32_t>>& patches, std::vector<double>& xy,
                   std::vector<uint8_t>& method, const SolveMergeOptions& opt, const JoinRule& can_join) {
  return SolveMerger(mesh, opp, patches, xy, method, opt, can_join).run();
}

}  // namespace gltfwarp
