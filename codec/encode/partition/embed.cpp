// The partition (encoder only). Growth follows Sorkine & Cohen-Or, "Warped
// Textures for UV Mapping Encoding" (2001), section 3: a seed triangle laid
// flat, then breadth-first rounds in which each candidate vertex is placed by
// the shared rule (layout.h: place_vertex) and rejected if one of its
// triangles exceeds tau, flips or overlaps the patch. Compact mode (issue 8)
// grows seeded balls: from the lowest free face, a geodesic ball sized to
// what tau allows (so each patch is a near-disc around its own seed); then
// merges adjacent patches while the union still replays within tau and stays
// compact; then straightens seams by moving notch and hole faces to the
// patch that surrounds them on two or three sides, when both still replay;
// a hole (1-3 faces inside one other patch) joins that patch, or else a
// corridor of its faces links the hole to the patch's outer border.
// Every regrowth of a merged or reshaped set seeds at the set's centre and
// falls back to its lowest face; the final patches keep the seed that grew
// them (format 1.1 stores it). Against lowest-face seeds only (1.0), this
// took Duck from 642 to 625 seam edges, Fox 154 to 143, CesiumMilkTruck
// 636 to 616. (Clustering first, Lloyd or VSA style, was measured with 1.0
// streams and lost: a cluster's lowest face, then the replay's only seed,
// falls anywhere in it, often on its rim, so only small clusters laid out.)
//
// Consistency with the replay (why the encoder's floats equal the decoder's):
// when candidate q is processed, let A be the patch-available faces holding q
// once with both other vertices placed. The encoder places q from a subset S
// of A and closes A \ S for this patch forever; q is accepted only if S holds
// a face that was available at the start of the round. Then the faces of the
// final patch that hold q with both others placed at that moment are exactly
// S, so the replay computes the same point. A rejected q closes the faces of
// A that were available at the round start (so the replay's candidate list
// for the round cannot contain q); its faces that opened mid-round stay open
// and q may join in the next round. The test EmbedEqualsReplay checks this.
#include "codec/encode/partition/embed.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <set>

#include "codec/core/distortion.h"
#include "codec/core/geometry2d.h"
#include "codec/core/layout_report.h"
#include "codec/core/topology.h"
#include "codec/encode/partition/notch_moves.h"
#include "codec/encode/partition/patch_pairs.h"
#include "codec/encode/partition/solve_merge.h"

namespace gltfwarp {
namespace {

// Face regrowths every budgeted pass may spend beyond its share per face:
// small meshes get every trial they can use, large ones stay linear.
constexpr double kBudgetFloor = 262144.0;

// The density rule (EmbedOptions::face_density): ln of each face's source
// texel density (NaN = unknown) and the largest spread ln(max_density_ratio)
// allowed inside one region or patch. The chart rule (face_chart) rides on
// it: each chart's values are offset by kChartSpacing times its id, so two
// charts' faces always differ by more than the limit.
struct DensityRule {
  bool active = false;
  double limit = 0;
  std::vector<double> ln;
  double at(uint32_t f) const { return active ? ln[f] : std::numeric_limits<double>::quiet_NaN(); }
  // Running [lo, hi] of a face set; true if face f can join it.
  bool admits(double lo, double hi, uint32_t f) const {
    const double d = at(f);
    return !(d == d) || !(lo <= hi) || std::max(hi, d) - std::min(lo, d) <= limit;
  }
  static void extend(double& lo, double& hi, double d) {
    if (d == d) lo = std::min(lo, d), hi = std::max(hi, d);
  }
  // ln of any finite density lies within +-745; offsets 4096 apart keep
  // every chart's band clear of the others' by more than any limit used,
  // and two values less than half of it apart are of one chart.
  static constexpr double kChartSpacing = 4096.0;
  static bool same_chart(double a, double b) { return std::abs(a - b) < 0.5 * kChartSpacing; }
};

DensityRule make_density_rule(uint32_t nf, const EmbedOptions& o) {
  DensityRule r;
  const bool density =
      o.face_density.size() == nf && o.max_density_ratio > 1 && std::isfinite(o.max_density_ratio);
  const bool charts = o.face_chart.size() == nf && nf > 0;
  if (!density && !charts) return r;
  constexpr double kChartSpacing = DensityRule::kChartSpacing;
  r.active = true;
  r.limit = density ? std::log(o.max_density_ratio) : 1.0;
  r.ln.resize(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    const double d = density ? o.face_density[f] : 1.0;
    const double chart = charts ? kChartSpacing * double(o.face_chart[f]) : 0.0;
    r.ln[f] = d > 0 && std::isfinite(d) ? chart + std::log(d) : std::numeric_limits<double>::quiet_NaN();
  }
  return r;
}

// A uniform hash grid over the 2D triangles of the patch being grown, reset
// per patch by a generation stamp so nothing is cleared.
class TriangleGrid {
 public:
  void init(size_t face_count, double cell) {
    size_t nb = 1024;
    while (nb < 2 * face_count && nb < (size_t{1} << 24)) nb <<= 1;
    head_.assign(nb, 0);
    head_gen_.assign(nb, 0);
    seen_.assign(face_count, 0);
    inv_cell_ = cell > 0 ? 1.0 / cell : 1.0;
  }
  void reset() {
    ++gen_;
    entries_.clear();
    big_.clear();
    all_.clear();
  }
  void insert(uint32_t f, const Vec2 P[3]) {
    all_.push_back(f);
    int x0, y0, x1, y1;
    if (!range(P, x0, y0, x1, y1)) {
      big_.push_back(f);
      return;
    }
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const uint64_t key = pack(x, y);
        const size_t b = bucket(key);
        if (head_gen_[b] != gen_) {
          head_gen_[b] = gen_;
          head_[b] = 0;
        }
        entries_.push_back({key, f, head_[b]});
        head_[b] = static_cast<uint32_t>(entries_.size());  // 1-based, 0 = end
      }
  }
  // True if triangle P overlaps (interiors) a stored triangle; xy gives the
  // stored triangles' corners (6 doubles per face).
  bool overlaps(const Vec2 P[3], const std::vector<double>& xy) {
    ++query_;
    const double lx = std::min({P[0].x, P[1].x, P[2].x}), hx = std::max({P[0].x, P[1].x, P[2].x});
    const double ly = std::min({P[0].y, P[1].y, P[2].y}), hy = std::max({P[0].y, P[1].y, P[2].y});
    auto test = [&](uint32_t g) {
      if (seen_[g] == query_) return false;
      seen_[g] = query_;
      const double* c = &xy[6 * size_t{g}];
      // Boxes that only touch cannot hold overlapping interiors.
      if (std::max({c[0], c[2], c[4]}) <= lx || std::min({c[0], c[2], c[4]}) >= hx ||
          std::max({c[1], c[3], c[5]}) <= ly || std::min({c[1], c[3], c[5]}) >= hy)
        return false;
      const Vec2 Q[3] = {{c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]}};
      return triangles_overlap(P, Q);
    };
    int x0, y0, x1, y1;
    if (!range(P, x0, y0, x1, y1)) {
      for (uint32_t g : all_)
        if (test(g)) return true;
      return false;
    }
    for (uint32_t g : big_)
      if (test(g)) return true;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const uint64_t key = pack(x, y);
        const size_t b = bucket(key);
        if (head_gen_[b] != gen_) continue;
        for (uint32_t e = head_[b]; e != 0; e = entries_[e - 1].next)
          if (entries_[e - 1].key == key && test(entries_[e - 1].face)) return true;
      }
    return false;
  }

 private:
  struct Entry {
    uint64_t key;
    uint32_t face, next;
  };
  static uint64_t pack(int x, int y) { return (uint64_t(uint32_t(x)) << 32) | uint64_t(uint32_t(y)); }
  size_t bucket(uint64_t key) const {
    return size_t((key * 0x9E3779B97F4A7C15ull) >> 40) & (head_.size() - 1);
  }
  // Cell range of P's bounding box; false when it is huge or not finite.
  bool range(const Vec2 P[3], int& x0, int& y0, int& x1, int& y1) const {
    double lx = P[0].x, hx = P[0].x, ly = P[0].y, hy = P[0].y;
    for (int k = 1; k < 3; ++k) {
      lx = std::min(lx, P[k].x), hx = std::max(hx, P[k].x);
      ly = std::min(ly, P[k].y), hy = std::max(hy, P[k].y);
    }
    lx *= inv_cell_, hx *= inv_cell_, ly *= inv_cell_, hy *= inv_cell_;
    if (!(lx > -1e9 && hx < 1e9 && ly > -1e9 && hy < 1e9)) return false;
    x0 = int(std::floor(lx)), x1 = int(std::floor(hx));
    y0 = int(std::floor(ly)), y1 = int(std::floor(hy));
    return double(x1 - x0 + 1) * double(y1 - y0 + 1) <= 64.0;
  }
  std::vector<uint32_t> head_, head_gen_, seen_, big_, all_;
  std::vector<Entry> entries_;
  uint32_t gen_ = 0, query_ = 0;
  double inv_cell_ = 1.0;
};

// The growth engine: grows one patch at a time from a seed, restricted to
// faces that are free and carry a given region label.
class Grower {
 public:
  const TriMesh& mesh() const { return m_; }
  Grower(const TriMesh& m, const VertexFaces& vf, const EmbedOptions& o) : m_(m), vf_(vf), opt_(o) {
    const uint32_t nf = m.face_count(), nv = m.vertex_count();
    face_patch.assign(nf, kNone);
    region.assign(nf, 0);
    xy.assign(size_t{nf} * 6, 0.0);
    placed_.assign(nv, 0);
    round_of_.assign(nv, 0);
    listed_.assign(nv, 0);
    closed_.assign(nf, 0);
    banned_.assign(nv, 0);
    pos_.resize(nv);
    double sum = 0;
    size_t n = 0;
    for (uint32_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const double l = length3(m, m.indices[3 * f + k], m.indices[3 * f + (k + 1) % 3]);
        if (l > 0 && std::isfinite(l)) sum += l, ++n;
      }
    grid_.init(nf, n ? 1.5 * sum / double(n) : 1.0);
  }

  uint32_t fail_face = kNone;                          // after grow: the first face it had to leave out
  std::vector<uint32_t> face_patch;                    // kNone = free
  std::vector<uint32_t> region;                        // growth stays within the seed's label
  std::vector<double> xy;                              // encoder positions per corner of assigned faces
  Vec2 position(uint32_t v) const { return pos_[v]; }  // of a vertex of the last grown patch

  // Grows patch `id` from `seed` (which must be free; it is the patch's lowest
  // face if the caller seeds at the lowest free face of the label). Appends
  // the patch's faces to `faces` and its placed vertices to `verts`.
  //
  // all_or_nothing: the caller needs every free face of the label in this
  // patch (a merge trial), so the first face closed ends the growth; returns
  // false then. plain: the paper's rule, a rejected vertex is discarded from
  // the patch for good and no subset of its faces is tried.
  bool grow(uint32_t seed, uint32_t id, std::vector<uint32_t>& faces, std::vector<uint32_t>& verts,
            bool all_or_nothing = false, bool plain = false) {
    ++gen_;
    grid_.reset();
    fail_face = kNone;
    faces.clear();
    verts.clear();
    const uint32_t label = region[seed];
    const uint32_t* idx = m_.indices.data();
    Vec2 sp[3];
    place_seed(m_, seed, sp);
    fresh_.clear();
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = idx[3 * seed + k];
      if (placed_[v] == gen_) continue;
      placed_[v] = gen_;
      round_of_[v] = 0;
      pos_[v] = sp[k];
      fresh_.push_back(v);
      verts.push_back(v);
    }
    assign(seed, id, sp);
    faces.push_back(seed);
    if (face_has_repeated_vertex(m_, seed) || orient2d_sign(sp[0], sp[1], sp[2]) <= 0 ||
        !face_within_tau(m_, seed, sp, opt_.tau))
      return !all_or_nothing;  // a degenerate seed stays a singleton patch
    grid_.insert(seed, sp);

    auto available = [&](uint32_t f) {
      return face_patch[f] == kNone && region[f] == label && closed_[f] != gen_;
    };
    for (uint32_t round = 1;; ++round) {
      ++list_stamp_;
      list_.clear();
      for (uint32_t v : fresh_)
        for (uint32_t i = vf_.offsets[v]; i < vf_.offsets[v + 1]; ++i) {
          const uint32_t f = vf_.faces[i];
          if (!available(f) || face_has_repeated_vertex(m_, f)) continue;
          const uint32_t* t = idx + 3 * f;
          for (int k = 0; k < 3; ++k) {
            const uint32_t q = t[k];
            if (placed_[q] == gen_ || listed_[q] == list_stamp_ || banned_[q] == gen_) continue;
            if (placed_[t[(k + 1) % 3]] == gen_ && placed_[t[(k + 2) % 3]] == gen_) {
              listed_[q] = list_stamp_;
              list_.push_back(q);
            }
          }
        }
      if (list_.empty()) break;
      std::sort(list_.begin(), list_.end());
      fresh_.clear();
      for (uint32_t q : list_) {
        // A: available faces with q once and both others placed, ascending.
        cand_.clear();
        for (uint32_t i = vf_.offsets[q]; i < vf_.offsets[q + 1]; ++i) {
          const uint32_t f = vf_.faces[i];
          if (!available(f) || face_has_repeated_vertex(m_, f)) continue;
          const uint32_t* t = idx + 3 * f;
          const int k = t[0] == q ? 0 : (t[1] == q ? 1 : 2);
          const uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
          if (placed_[a] != gen_ || placed_[b] != gen_) continue;
          cand_.push_back({f, a, b, k, round_of_[a] < round && round_of_[b] < round, true});
        }
        const bool accepted = try_place(q, plain ? 1 : opt_.place_attempts);
        if (accepted) {
          placed_[q] = gen_;
          round_of_[q] = round;
          pos_[q] = trial_;
          fresh_.push_back(q);
          verts.push_back(q);
          for (const Cand& c : cand_) {
            if (!c.in) {
              closed_[c.f] = gen_;
              fail_face = c.f;
              if (all_or_nothing) return false;
              continue;
            }
            Vec2 P[3];
            corners(c, trial_, P);
            assign(c.f, id, P);
            grid_.insert(c.f, P);
            faces.push_back(c.f);
          }
        } else {
          if (plain) banned_[q] = gen_;
          for (const Cand& c : cand_)
            if (c.at_start || plain) closed_[c.f] = gen_;
          if (!cand_.empty()) fail_face = cand_.front().f;
          if (all_or_nothing && !cand_.empty()) return false;
        }
      }
    }
    return true;
  }

 private:
  struct Cand {
    uint32_t f, a, b;
    int k;          // q's corner in f
    bool at_start;  // available with both others placed when the round began
    bool in;        // member of the subset S being tried
  };

  void corners(const Cand& c, Vec2 q, Vec2 P[3]) const {
    P[c.k] = q;
    P[(c.k + 1) % 3] = pos_[c.a];
    P[(c.k + 2) % 3] = pos_[c.b];
  }

  void assign(uint32_t f, uint32_t id, const Vec2 P[3]) {
    face_patch[f] = id;
    for (int k = 0; k < 3; ++k) {
      xy[6 * size_t{f} + 2 * k] = P[k].x;
      xy[6 * size_t{f} + 2 * k + 1] = P[k].y;
    }
  }

  // Chooses S within cand_ (marking .in) and the point trial_; false = reject.
  bool try_place(uint32_t q, int attempts) {
    for (int attempt = 0; attempt < attempts; ++attempt) {
      bool any_start = false;
      unf_.clear();
      for (const Cand& c : cand_) {
        if (!c.in) continue;
        any_start |= c.at_start;
        unf_.push_back(make_unfolding(m_, q, c.a, c.b, pos_[c.a], pos_[c.b]));
      }
      if (!any_start) return false;
      trial_ = place_vertex(unf_);
      bool all_ok = true;
      tris_.clear();
      for (Cand& c : cand_) {
        if (!c.in) continue;
        Vec2 P[3];
        corners(c, trial_, P);
        bool ok = orient2d_sign(P[0], P[1], P[2]) > 0 && face_within_tau(m_, c.f, P, opt_.tau) &&
                  !grid_.overlaps(P, xy);
        for (size_t j = 0; ok && j < tris_.size(); j += 3) ok = !triangles_overlap(P, &tris_[j]);
        if (ok) {
          tris_.insert(tris_.end(), P, P + 3);
        } else {
          c.in = false;
          all_ok = false;
        }
      }
      if (all_ok) return true;
    }
    return false;
  }

  const TriMesh& m_;
  const VertexFaces& vf_;
  const EmbedOptions& opt_;
  std::vector<uint32_t> placed_, round_of_, listed_, closed_, banned_;
  std::vector<Vec2> pos_;
  std::vector<uint32_t> fresh_, list_;
  std::vector<Cand> cand_;
  std::vector<Unfolding> unf_;
  std::vector<Vec2> tris_;
  Vec2 trial_;
  TriangleGrid grid_;
  uint32_t gen_ = 0, list_stamp_ = 0;
};

// Fill from the patch's placed vertices (the hull only needs each once).
double fill_from_vertices(const Grower& g, std::span<const uint32_t> faces, std::span<const uint32_t> verts,
                          std::vector<Vec2>& scratch) {
  double area = 0;
  for (uint32_t f : faces) {
    const double* c = &g.xy[6 * size_t{f}];
    area += std::fabs(orient2d({c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]})) * 0.5;
  }
  scratch.clear();
  for (uint32_t v : verts) scratch.push_back(g.position(v));
  const OrientedRect r = min_area_rect(convex_hull(scratch));
  return r.area > 0 ? std::min(1.0, area / r.area) : 1.0;
}

// Unit normal (zero for degenerate faces), centroid and area of every face,
// in double: what the clustering passes measure distances and cones with.
struct FaceFrames {
  std::vector<double> normal, centroid, area;  // 3, 3 and 1 per face
};

FaceFrames face_frames(const TriMesh& m) {
  const uint32_t nf = m.face_count();
  FaceFrames fr;
  fr.normal.assign(size_t{nf} * 3, 0.0);
  fr.centroid.assign(size_t{nf} * 3, 0.0);
  fr.area.assign(nf, 0.0);
  const float* p = m.positions.data();
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t* t = &m.indices[3 * f];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = double(p[3 * t[1] + k]) - double(p[3 * t[0] + k]);
      e2[k] = double(p[3 * t[2] + k]) - double(p[3 * t[0] + k]);
      fr.centroid[3 * f + k] = (double(p[3 * t[0] + k]) + p[3 * t[1] + k] + p[3 * t[2] + k]) / 3.0;
    }
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    fr.area[f] = 0.5 * len;
    if (len > 0 && std::isfinite(len))
      for (int k = 0; k < 3; ++k) fr.normal[3 * f + k] = n[k] / len;
  }
  return fr;
}

// The seed a face set grows best from (format 1.1 stores it): its centre,
// so the replay's rounds reach the rim after a radius, not a diameter, and
// the distortion they accumulate stays low. Approximates the 1-centre of the
// set's dual graph (edge length = centroid distance) by a double sweep: from
// the lowest face to the farthest face a, from a to the farthest b; the seed
// minimises max(d_a, d_b) (exact on a path, near it on discs and strips).
// Degenerate faces are never chosen; kNone if the set has no other.
class SeedPicker {
 public:
  SeedPicker(const TriMesh& m, const std::vector<uint32_t>& opp, const FaceFrames& fr)
      : m_(m), opp_(opp), fr_(fr) {
    const uint32_t nf = m.face_count();
    member_.assign(nf, 0);
    da_.assign(nf, 0.0);
    db_.assign(nf, 0.0);
  }

  uint32_t centre(std::span<const uint32_t> set) {
    if (set.empty()) return kNone;
    ++stamp_;
    uint32_t low = kNone;
    for (uint32_t f : set) member_[f] = stamp_, low = std::min(low, f);
    if (set.size() <= 2) return usable(low) ? low : first_usable(set);
    // Faces a sweep does not reach (a set in pieces) stay infinitely far.
    constexpr double inf = std::numeric_limits<double>::infinity();
    for (uint32_t f : set) da_[f] = inf;
    const uint32_t a = sweep(low, da_);
    for (uint32_t f : set) da_[f] = inf, db_[f] = inf;
    const uint32_t b = sweep(a, da_);
    sweep(b, db_);
    uint32_t best = kNone;
    double best_d = std::numeric_limits<double>::infinity();
    for (uint32_t f : set) {
      if (!usable(f)) continue;
      const double d = std::max(da_[f], db_[f]);
      if (d < best_d || (d == best_d && f < best)) best_d = d, best = f;
    }
    return best;
  }

 private:
  bool usable(uint32_t f) const { return fr_.area[f] > 0 && !face_has_repeated_vertex(m_, f); }
  uint32_t first_usable(std::span<const uint32_t> set) const {
    uint32_t best = kNone;
    for (uint32_t f : set)
      if (usable(f)) best = std::min(best, f);
    return best;
  }

  // Dijkstra over the set from `from` into dist (infinity where unreached);
  // returns the farthest face reached.
  uint32_t sweep(uint32_t from, std::vector<double>& dist) {
    using Item = std::pair<double, uint32_t>;
    heap_.clear();
    auto push = [&](double d, uint32_t f) {
      heap_.push_back({d, f});
      std::push_heap(heap_.begin(), heap_.end(), std::greater<Item>());
    };
    dist[from] = 0;
    push(0.0, from);
    uint32_t far = from;
    double far_d = 0;
    const double* c = fr_.centroid.data();
    while (!heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), std::greater<Item>());
      const auto [d, f] = heap_.back();
      heap_.pop_back();
      if (d > dist[f]) continue;
      if (d > far_d || (d == far_d && f < far)) far_d = d, far = f;
      for (int k = 0; k < 3; ++k) {
        const uint32_t o = opp_[3 * f + k];
        if (o == kNone) continue;
        const uint32_t h = o / 3;
        if (member_[h] != stamp_) continue;
        const double dx = c[3 * h] - c[3 * f], dy = c[3 * h + 1] - c[3 * f + 1],
                     dz = c[3 * h + 2] - c[3 * f + 2];
        const double nd = d + std::sqrt(dx * dx + dy * dy + dz * dz);
        if (dist[h] <= nd) continue;
        dist[h] = nd;
        push(nd, h);
      }
    }
    return far;
  }

  const TriMesh& m_;
  const std::vector<uint32_t>& opp_;
  const FaceFrames& fr_;
  std::vector<uint32_t> member_;
  std::vector<double> da_, db_;
  std::vector<std::pair<double, uint32_t>> heap_;
  uint32_t stamp_ = 0;
};

// A region label no face carries yet (for sets regrown on their own).
uint32_t first_free_label(const Grower& g) {
  uint32_t label = 0;
  for (uint32_t r : g.region) label = std::max(label, r == kNone ? 0 : r + 1);
  return label;
}

// Regrows the face set `set` (whose faces must be free and carry one label)
// as patch `id` and reports whether it grew whole. Tries the set's centre
// first, then its lowest face: the replay grows from either (format 1.1
// stores the seed), and each succeeds on sets where the other fails. On
// failure the faces of the last attempt are still assigned (the caller frees
// them); `seed` receives the seed that grew the set.
bool regrow_whole(Grower& g, SeedPicker& picker, std::span<const uint32_t> set, uint32_t id,
                  std::vector<uint32_t>& faces, std::vector<uint32_t>& verts, uint32_t* seed = nullptr) {
  faces.clear();
  if (set.empty()) return false;
  const uint32_t centre = picker.centre(set);
  if (centre != kNone && g.grow(centre, id, faces, verts, true) && faces.size() == set.size()) {
    if (seed) *seed = centre;
    return true;
  }
  const uint32_t low = *std::min_element(set.begin(), set.end());
  if (low == centre) return false;
  for (uint32_t f : faces) g.face_patch[f] = kNone;
  if (g.grow(low, id, faces, verts, true) && faces.size() == set.size()) {
    if (seed) *seed = low;
    return true;
  }
  return false;
}

// Grows patches covering every face: for each label, seeds at the lowest
// free face of that label until the label is covered. Returns the patches'
// face lists (patch ids are their index; creation order).
void grow_all(Grower& g, std::vector<std::vector<uint32_t>>& patches, bool plain = false) {
  const uint32_t nf = static_cast<uint32_t>(g.face_patch.size());
  std::vector<uint32_t> faces, verts;
  for (uint32_t f = 0; f < nf; ++f) {
    if (g.face_patch[f] != kNone) continue;
    const uint32_t id = static_cast<uint32_t>(patches.size());
    g.grow(f, id, faces, verts, false, plain);
    patches.push_back(faces);
  }
}

// Compact mode, step 1: seeded balls. From the lowest free face (the
// patch's seed in the replay, so the replay's growth starts at the ball's
// centre, not at its rim as with clusters whose lowest face falls anywhere),
// a ball of free faces in Dijkstra order of a geodesic cost that grows with
// the normal's deviation from the seed's. The ball is sized to what tau
// allows: the prefix of that order doubles while it grows whole; at the
// first failure it is cut just before the face the growth left out, and
// grown once more keeping what fits (only its rim can lose faces). Balls
// already bordered by earlier patches come out as half-discs around their
// seed, which still fill their rectangles (pi/4). A ball that lies flat but
// curled (around a tube) is shrunk while that raises its fill.
void grow_balls(Grower& g, const std::vector<uint32_t>& opp, const FaceFrames& fr, const EmbedOptions& opt,
                const DensityRule& dr, std::vector<std::vector<uint32_t>>& patches) {
  const TriMesh& m = g.mesh();
  const uint32_t nf = m.face_count();
  const std::vector<double>&nrm = fr.normal, &cen = fr.centroid, &area = fr.area;
  auto floodable = [&](uint32_t f) { return area[f] > 0 && !face_has_repeated_vertex(m, f); };
  std::vector<double> dist(nf, std::numeric_limits<double>::infinity());
  std::vector<uint32_t> stamp(nf, 0), done(nf, 0), rank(nf, 0), ord, faces, verts;
  size_t last_good = 0;
  std::vector<Vec2> scratch;
  const double min_fill = opt.ball_min_fill;
  const int ball_shrinks = opt.ball_shrinks;
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  uint32_t label = 1, ball = 0;
  std::fill(g.region.begin(), g.region.end(), 0u);
  for (uint32_t s = 0; s < nf; ++s) {
    if (g.face_patch[s] != kNone) continue;
    const uint32_t id = static_cast<uint32_t>(patches.size());
    ++ball;
    ord.clear();
    heap = {};
    if (floodable(s)) {
      dist[s] = 0, stamp[s] = ball;
      heap.push({0.0, s});
    } else {
      ord.push_back(s);
    }
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const double* ns = &nrm[3 * size_t{s}];
    // Extends ord to n faces (fewer when the ball runs out).
    auto extend = [&](size_t n) {
      while (ord.size() < n && !heap.empty()) {
        const auto [d, f] = heap.top();
        heap.pop();
        if (done[f] == ball || d > dist[f]) continue;
        if (!dr.admits(lo, hi, f)) continue;
        DensityRule::extend(lo, hi, dr.at(f));
        done[f] = ball;
        rank[f] = static_cast<uint32_t>(ord.size());
        ord.push_back(f);
        for (int k = 0; k < 3; ++k) {
          const uint32_t o = opp[3 * f + k];
          if (o == kNone) continue;
          const uint32_t h = o / 3;
          if (g.face_patch[h] != kNone || !floodable(h) || done[h] == ball) continue;
          const double dx = cen[3 * h] - cen[3 * f], dy = cen[3 * h + 1] - cen[3 * f + 1],
                       dz = cen[3 * h + 2] - cen[3 * f + 2];
          const double dev = 1.0 - (nrm[3 * h] * ns[0] + nrm[3 * h + 1] * ns[1] + nrm[3 * h + 2] * ns[2]);
          const double nd = d + std::sqrt(dx * dx + dy * dy + dz * dz) * (1.0 + opt.normal_weight * dev);
          if (stamp[h] == ball && dist[h] <= nd) continue;
          stamp[h] = ball, dist[h] = nd;
          heap.push({nd, h});
        }
      }
    };
    // Trial: does the prefix of n faces grow whole?
    auto trial = [&](size_t n, bool whole) {
      ++label;
      for (size_t i = 0; i < n; ++i) g.region[ord[i]] = label;
      const bool ok = g.grow(s, id, faces, verts, whole) && faces.size() == n;
      if (whole)
        for (uint32_t f : faces) g.face_patch[f] = kNone;
      return ok;
    };
    // Largest prefix that grows whole: start at twice the last ball's size,
    // double while it grows whole, and after a failure cut the prefix just
    // before the face the growth had to leave out.
    size_t good = 0, n = std::max<size_t>(64, 2 * last_good);
    for (int tries = 0; tries < 12; ++tries) {
      extend(n);
      const size_t k = std::min(n, ord.size());
      if (k <= good) break;
      if (trial(k, true)) {
        good = k;
        if (ord.size() < n) break;
        n = 2 * k;
        continue;
      }
      size_t cut = k - 1;
      const uint32_t bad = g.fail_face;
      if (bad != kNone && done[bad] == ball)
        cut = std::min(cut, size_t(rank[bad]));
      else
        cut = std::min(cut, k - k / 4);
      cut = std::min(cut, k - k / 16);
      if (cut <= good) break;
      // Up to the face left out, the growth (without "whole") keeps the
      // ball and drops only what fails near its rim; no further trial.
      extend(cut);
      good = std::min(cut, ord.size());
      break;
    }
    last_good = good;
    size_t take = good > 0 ? good : std::min<size_t>(ord.size(), 8);
    trial(take, false);
    // A ball that lies flat but curled (around a tube, say) fills its
    // rectangle badly: shrink it a few times, keep the best fill.
    double fill = fill_from_vertices(g, faces, verts, scratch);
    size_t best = take;
    double best_fill = fill;
    for (int t = 0; t < ball_shrinks && best_fill < min_fill && take > 32; ++t) {
      for (uint32_t f : faces) g.face_patch[f] = kNone;
      take -= take / 4;
      trial(take, false);
      fill = fill_from_vertices(g, faces, verts, scratch);
      if (fill > best_fill) best_fill = fill, best = take;
    }
    if (best != take) {
      for (uint32_t f : faces) g.face_patch[f] = kNone;
      trial(best, false);
    }
    patches.push_back(faces);
  }
}

// Area-weighted normal sum of a face set (out[0..2]) and the largest angle
// of a face normal to it (out[3], radians).
void patch_cone(const TriMesh& m, std::span<const uint32_t> faces, double out[4]) {
  const float* p = m.positions.data();
  double s[3] = {0, 0, 0};
  std::vector<double> n(faces.size() * 3);
  for (size_t i = 0; i < faces.size(); ++i) {
    const uint32_t* t = &m.indices[3 * faces[i]];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = double(p[3 * t[1] + k]) - double(p[3 * t[0] + k]);
      e2[k] = double(p[3 * t[2] + k]) - double(p[3 * t[0] + k]);
    }
    n[3 * i] = e1[1] * e2[2] - e1[2] * e2[1];
    n[3 * i + 1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[3 * i + 2] = e1[0] * e2[1] - e1[1] * e2[0];
    for (int k = 0; k < 3; ++k) s[k] += n[3 * i + k];
  }
  const double ls = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  double worst = 1.0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const double* x = &n[3 * i];
    const double lx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    if (lx > 0 && ls > 0) worst = std::min(worst, (x[0] * s[0] + x[1] * s[1] + x[2] * s[2]) / (lx * ls));
  }
  out[0] = s[0], out[1] = s[1], out[2] = s[2];
  out[3] = std::acos(std::clamp(worst, -1.0, 1.0));
}

// Compact mode, step 3: merge adjacent patches, most shared edges first,
// when the union regrows completely from its lowest face (so it replays
// within tau, unflipped and overlap-free) and stays compact.
void merge_patches(Grower& g, SeedPicker& picker, const std::vector<uint32_t>& opp, const EmbedOptions& opt,
                   double budget_x, const DensityRule& dr, std::vector<std::vector<uint32_t>>& patches) {
  const uint32_t np = static_cast<uint32_t>(patches.size());
  std::vector<double> fill(np, 1.0);
  std::vector<Vec2> scratch;
  for (uint32_t p = 0; p < np; ++p) fill[p] = patch_fill(patches[p], g.xy, scratch);
  std::vector<uint32_t> touched(np, 0), version(np, 0), faces, verts, unite;
  std::vector<double> cone(size_t{np} * 4);
  for (uint32_t p = 0; p < np; ++p) patch_cone(g.mesh(), patches[p], &cone[4 * size_t{p}]);
  std::set<std::array<uint32_t, 4>> failed;
  // Trials regrow whole unions; a budget in faces keeps the pass linear.
  double budget = budget_x * double(g.face_patch.size()) + kBudgetFloor;
  std::vector<double> saved;
  uint32_t next_label = 0;
  for (uint32_t f : g.region) next_label = std::max(next_label, f == kNone ? 0 : f + 1);
  std::vector<uint64_t> keys;
  std::vector<PatchPair> pairs;
  for (int round = 1; round <= opt.merge_rounds; ++round) {
    adjacent_patch_pairs(opp, g.face_patch, keys, pairs);
    bool merged_any = false;
    for (const PatchPair& pr : pairs) {
      if (touched[pr.a] == uint32_t(round) || touched[pr.b] == uint32_t(round)) continue;
      // A pair that failed is not retried until one side has changed.
      if (budget < double(patches[pr.a].size() + patches[pr.b].size())) return;
      const std::array<uint32_t, 4> memo = {pr.a, version[pr.a], pr.b, version[pr.b]};
      if (failed.count(memo)) continue;
      // A union whose normals spread too far cannot lie flat within tau
      // (a spherical cap's limit is far below this); skip the costly trial.
      {
        const double* na = &cone[4 * size_t{pr.a}];
        const double* nb = &cone[4 * size_t{pr.b}];
        const double u[3] = {na[0] + nb[0], na[1] + nb[1], na[2] + nb[2]};
        auto ang = [&](const double* x) {
          const double lx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
          const double lu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
          if (!(lx > 0) || !(lu > 0)) return 0.0;
          const double c = (x[0] * u[0] + x[1] * u[1] + x[2] * u[2]) / (lx * lu);
          return std::acos(std::clamp(c, -1.0, 1.0));
        };
        const double spread = std::max(ang(na) + na[3], ang(nb) + nb[3]);
        if (spread > opt.merge_max_cone_deg * 3.14159265358979323846 / 180.0) continue;
      }
      std::vector<uint32_t>& A = patches[pr.a];
      std::vector<uint32_t>& B = patches[pr.b];
      if (dr.active) {  // the union must keep the density rule
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (uint32_t f : A) DensityRule::extend(lo, hi, dr.at(f));
        for (uint32_t f : B) DensityRule::extend(lo, hi, dr.at(f));
        if (lo <= hi && hi - lo > dr.limit) continue;
      }
      unite.assign(A.begin(), A.end());
      unite.insert(unite.end(), B.begin(), B.end());
      saved.resize(unite.size() * 6);
      const uint32_t label = next_label++;
      for (size_t i = 0; i < unite.size(); ++i) {
        const uint32_t f = unite[i];
        std::copy_n(&g.xy[6 * size_t{f}], 6, &saved[6 * i]);
        g.region[f] = label;
        g.face_patch[f] = kNone;
      }
      budget -= double(unite.size());
      bool ok = regrow_whole(g, picker, unite, pr.a, faces, verts);
      double fu = 0;
      if (ok) {
        fu = fill_from_vertices(g, faces, verts, scratch);
        const size_t small = std::min(A.size(), B.size());
        ok = fu >= std::min(opt.merge_min_fill, std::min(fill[pr.a], fill[pr.b])) ||
             small <= opt.merge_small_faces;
      }
      touched[pr.a] = touched[pr.b] = uint32_t(round);
      if (ok) {
        A = faces;
        B.clear();
        fill[pr.a] = fu;
        ++version[pr.a];
        patch_cone(g.mesh(), A, &cone[4 * size_t{pr.a}]);
        merged_any = true;
      } else {
        for (uint32_t f : faces) g.face_patch[f] = kNone;
        for (size_t i = 0; i < A.size() + B.size(); ++i) {
          const uint32_t f = unite[i];
          g.face_patch[f] = i < A.size() ? pr.a : pr.b;
          std::copy_n(&saved[6 * i], 6, &g.xy[6 * size_t{f}]);
        }
        // Leave both free for another partner this round.
        touched[pr.a] = touched[pr.b] = 0;
        failed.insert(memo);
      }
    }
    if (!merged_any) break;
  }
}

// Seam straightening: a face with two or three edges on patch B moves to B
// (one or three seam edges fewer, and a notch or hole gone) when both
// patches still regrow whole afterwards. Moves between one pair of patches
// are tried as a batch, then as halves. Returns the number of faces moved.
size_t straighten_seams(Grower& g, SeedPicker& picker, const std::vector<uint32_t>& opp, int rounds,
                        double budget_x, const DensityRule& dr, std::vector<std::vector<uint32_t>>& patches) {
  const uint32_t nf = static_cast<uint32_t>(g.face_patch.size());
  double budget = budget_x * double(nf) + kBudgetFloor;
  std::vector<NotchGroup> groups;
  std::vector<uint32_t> touched(patches.size(), 0), faces, verts, keep, grow_b;
  std::vector<double> saved;
  std::vector<uint32_t> saved_faces, saved_patch;
  uint32_t label = first_free_label(g);
  size_t moved_total = 0;
  std::vector<NotchMove> moves;
  // Regrows the face set `set` as patch `id`; true if it grew whole.
  auto regrow = [&](const std::vector<uint32_t>& set, uint32_t id) {
    if (set.empty()) return true;
    const uint32_t lab = label++;
    for (uint32_t f : set) g.region[f] = lab, g.face_patch[f] = kNone;
    const bool ok = regrow_whole(g, picker, set, id, faces, verts);
    if (!ok)
      for (uint32_t f : faces) g.face_patch[f] = kNone;
    return ok;
  };
  for (int round = 1; round <= rounds; ++round) {
    notch_moves(opp, g.face_patch, moves, groups);
    if (moves.empty()) break;
    size_t moved = 0;
    for (const NotchGroup& gr : groups) {
      const size_t i = gr.begin, j = gr.end;
      const uint32_t a = moves[i].a, b = moves[i].b;
      if (touched[a] == uint32_t(round) || touched[b] == uint32_t(round)) continue;
      if (budget < double(patches[a].size() + patches[b].size())) return moved_total + moved;
      std::vector<uint32_t>& A = patches[a];
      std::vector<uint32_t>& B = patches[b];
      if (dr.active) {  // B with the moved faces must keep the density rule
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (uint32_t f : B) DensityRule::extend(lo, hi, dr.at(f));
        for (size_t t = i; t < j; ++t) DensityRule::extend(lo, hi, dr.at(moves[t].f));
        if (lo <= hi && hi - lo > dr.limit) continue;
      }
      // Save both patches' state.
      saved_faces.assign(A.begin(), A.end());
      saved_faces.insert(saved_faces.end(), B.begin(), B.end());
      saved.resize(saved_faces.size() * 6);
      for (size_t t = 0; t < saved_faces.size(); ++t)
        std::copy_n(&g.xy[6 * size_t{saved_faces[t]}], 6, &saved[6 * t]);
      size_t count = j - i;
      bool done = false;
      for (int attempt = 0; attempt < 2 && count > 0 && !done; ++attempt, count /= 2) {
        budget -= double(A.size() + B.size());
        for (size_t t = i; t < i + count; ++t) g.face_patch[moves[t].f] = kNone;  // mark
        keep.clear();
        for (uint32_t f : A)
          if (g.face_patch[f] != kNone) keep.push_back(f);
        grow_b.assign(B.begin(), B.end());
        for (size_t t = i; t < i + count; ++t) grow_b.push_back(moves[t].f);
        for (size_t t = i; t < i + count; ++t) g.face_patch[moves[t].f] = a;  // unmark
        if (regrow(keep, a) && regrow(grow_b, b)) {
          A = keep;
          B = grow_b;
          moved += count;
          done = true;
        } else {
          for (size_t t = 0; t < saved_faces.size(); ++t) {
            const uint32_t f = saved_faces[t];
            g.face_patch[f] = t < A.size() ? a : b;
            std::copy_n(&saved[6 * t], 6, &g.xy[6 * size_t{f}]);
          }
        }
      }
      if (done) touched[a] = touched[b] = uint32_t(round);
    }
    moved_total += moved;
    if (moved == 0) break;
  }
  return moved_total;
}

// Holes (issue 8): a patch of 1 to 3 faces whose every edge borders one
// other patch B joins B when B with it still regrows whole. Unbudgeted:
// holes are few, and each trial costs one regrowth of B.
void absorb_holes(Grower& g, SeedPicker& picker, const std::vector<uint32_t>& opp, const DensityRule& dr,
                  std::vector<std::vector<uint32_t>>& patches) {
  std::vector<uint32_t> faces, verts, unite;
  std::vector<double> saved;
  uint32_t label = first_free_label(g);
  for (uint32_t p = 0; p < patches.size(); ++p) {
    const std::vector<uint32_t>& H = patches[p];
    const uint32_t b = hole_host(opp, g.face_patch, H, p);
    if (b == kNone) continue;
    std::vector<uint32_t>& B = patches[b];
    if (dr.active) {
      // Faces with less source detail than B's (stretched source UVs) only
      // gain texels in B, so a hole may sit below B's density range; one
      // above it, or in another chart, stays apart. Duck: 4 holes -> 0.
      const double inf = std::numeric_limits<double>::infinity();
      double blo = inf, bhi = -inf, hlo = inf, hhi = -inf;
      for (uint32_t f : B) DensityRule::extend(blo, bhi, dr.at(f));
      for (uint32_t f : H) DensityRule::extend(hlo, hhi, dr.at(f));
      if (blo <= bhi && hlo <= hhi && (hhi - blo > dr.limit || !DensityRule::same_chart(hlo, blo))) continue;
    }
    unite.assign(B.begin(), B.end());
    unite.insert(unite.end(), H.begin(), H.end());
    saved.resize(unite.size() * 6);
    const uint32_t lab = label++;
    for (size_t i = 0; i < unite.size(); ++i) {
      const uint32_t f = unite[i];
      std::copy_n(&g.xy[6 * size_t{f}], 6, &saved[6 * i]);
      g.region[f] = lab, g.face_patch[f] = kNone;
    }
    if (regrow_whole(g, picker, unite, b, faces, verts)) {
      B = faces;
      patches[p].clear();
      continue;
    }
    for (uint32_t f : faces) g.face_patch[f] = kNone;
    for (size_t i = 0; i < unite.size(); ++i) {
      const uint32_t f = unite[i];
      g.face_patch[f] = i < B.size() ? b : p;
      std::copy_n(&saved[6 * i], 6, &g.xy[6 * size_t{f}]);
    }
  }
}

// Holes that absorb_holes leaves (the host cannot take them within tau,
// typically where the hole sits on a cone point the host wraps around, or
// the density rule keeps them apart): a corridor of the host's faces, the
// shortest in face steps from the hole to the host's outer border, leaves
// the host, so that the host becomes a disc again and the hole borders a
// second patch. The corridor joins the hole where the density rule allows,
// else it is a patch of its own. Accepted only when every changed set
// regrows whole; the first few exits in breadth-first order are tried.
// A host with no outer border (host and hole close a part, a cube cut
// 9 + 3) encloses nothing and is left. Each corridor face costs about one
// seam edge; the host loses an inner border that the packer cannot use.
void open_holes(Grower& g, SeedPicker& picker, const std::vector<uint32_t>& opp, const DensityRule& dr,
                std::vector<std::vector<uint32_t>>& patches) {
  constexpr size_t kExitsTried = 12;
  const uint32_t nf = static_cast<uint32_t>(g.face_patch.size());
  std::vector<uint32_t> parent(nf, kNone), queue, exits, visited, faces, verts, grown_b, host_rest, opened;
  std::vector<double> saved;
  uint32_t label = first_free_label(g);
  const size_t holes_end = patches.size();  // corridors of their own are not holes
  for (uint32_t p = 0; p < holes_end; ++p) {
    const uint32_t b = hole_host(opp, g.face_patch, patches[p], p);
    if (b == kNone) continue;
    // Breadth-first over the host's faces from those beside the hole; an
    // exit is a host face with an edge on the mesh border or a third patch.
    queue.clear(), exits.clear(), visited.clear();
    for (uint32_t f : patches[p])
      for (int k = 0; k < 3; ++k) {
        const uint32_t n = opp[3 * f + k] / 3;
        if (g.face_patch[n] == b && parent[n] == kNone)
          parent[n] = n, queue.push_back(n), visited.push_back(n);
      }
    for (size_t i = 0; i < queue.size() && exits.size() < kExitsTried; ++i) {
      const uint32_t f = queue[i];
      bool exit = false;
      for (int k = 0; k < 3; ++k) {
        const uint32_t o = opp[3 * f + k];
        if (o == kNone || (g.face_patch[o / 3] != b && g.face_patch[o / 3] != p)) exit = true;
        if (o == kNone || g.face_patch[o / 3] != b || parent[o / 3] != kNone) continue;
        parent[o / 3] = f, queue.push_back(o / 3), visited.push_back(o / 3);
      }
      if (exit) exits.push_back(f);
    }
    for (uint32_t e : exits) {
      opened.clear();
      for (uint32_t f = e;; f = parent[f]) {
        opened.push_back(f);
        if (parent[f] == f) break;
      }
      bool join = true;
      if (dr.active) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (uint32_t f : patches[p]) DensityRule::extend(lo, hi, dr.at(f));
        for (uint32_t f : opened) join = join && dr.admits(lo, hi, f), DensityRule::extend(lo, hi, dr.at(f));
      }
      const uint32_t id = join ? p : static_cast<uint32_t>(patches.size());
      if (join) opened.insert(opened.end(), patches[p].begin(), patches[p].end());
      std::vector<uint32_t>& B = patches[b];
      for (uint32_t f : opened) g.face_patch[f] = kNone;  // mark
      host_rest.clear();
      for (uint32_t f : B)
        if (g.face_patch[f] == b) host_rest.push_back(f);
      // Saved: B's positions, then the hole's when it joins.
      const std::span<const uint32_t> hole =
          join ? std::span<const uint32_t>(patches[p]) : std::span<const uint32_t>();
      saved.resize((B.size() + hole.size()) * 6);
      size_t i = 0;
      for (uint32_t f : B) std::copy_n(&g.xy[6 * size_t{f}], 6, &saved[6 * i++]);
      for (uint32_t f : hole) std::copy_n(&g.xy[6 * size_t{f}], 6, &saved[6 * i++]);
      const uint32_t lb = label++, lh = label++;
      for (uint32_t f : host_rest) g.region[f] = lb, g.face_patch[f] = kNone;
      for (uint32_t f : opened) g.region[f] = lh, g.face_patch[f] = kNone;
      if (regrow_whole(g, picker, host_rest, b, grown_b, verts) &&
          regrow_whole(g, picker, opened, id, faces, verts)) {
        B = grown_b;
        if (join)
          patches[p] = faces;
        else
          patches.push_back(faces);  // B and hole not used after this
        break;
      }
      for (uint32_t f : B) g.face_patch[f] = kNone;
      for (uint32_t f : hole) g.face_patch[f] = kNone;
      i = 0;
      for (uint32_t f : B) g.face_patch[f] = b, std::copy_n(&saved[6 * i++], 6, &g.xy[6 * size_t{f}]);
      for (uint32_t f : hole) g.face_patch[f] = p, std::copy_n(&saved[6 * i++], 6, &g.xy[6 * size_t{f}]);
    }
    for (uint32_t f : visited) parent[f] = kNone;
  }
}

}  // namespace

Embedding embed(const TriMesh& mesh, const EmbedOptions& opt) {
  Embedding out;
  if (!mesh_indices_valid(mesh)) {
    out.status = LayoutStatus::bad_mesh;
    return out;
  }
  const uint32_t nf = mesh.face_count();
  const VertexFaces vf = build_vertex_faces(mesh);
  const std::vector<uint32_t> opp = build_opposite_corners(mesh, vf);
  Grower g(mesh, vf, opt);
  std::vector<std::vector<uint32_t>> patches;
  std::vector<uint32_t> seed_of;  // per entry of patches (compact mode)
  std::vector<uint8_t> methods;   // per entry of patches, when solve merges ran
  if (opt.mode == PartitionMode::compact) {
    const FaceFrames frames = face_frames(mesh);
    SeedPicker picker(mesh, opp, frames);
    const DensityRule dr = make_density_rule(nf, opt);
    grow_balls(g, opp, frames, opt, dr, patches);
    if (opt.merge) merge_patches(g, picker, opp, opt, opt.merge_budget, dr, patches);
    if (opt.straighten_rounds > 0) {
      straighten_seams(g, picker, opp, opt.straighten_rounds, opt.straighten_budget, dr, patches);
      if (opt.merge) merge_patches(g, picker, opp, opt, opt.remerge_budget, dr, patches);
    }
    absorb_holes(g, picker, opp, dr, patches);
    open_holes(g, picker, opp, dr, patches);
    // Final pass: regrow every patch's face set from its centre, so that the
    // recorded encoder positions come from one growth of the final sets (a
    // set that did not regrow whole is split: its leftovers grow from their
    // lowest faces, which keeps the result valid).
    std::vector<std::vector<uint32_t>> sets;
    sets.swap(patches);
    for (uint32_t p = 0; p < sets.size(); ++p)
      for (uint32_t f : sets[p]) g.region[f] = p, g.face_patch[f] = kNone;
    std::vector<uint32_t> faces, verts;
    for (uint32_t p = 0; p < sets.size(); ++p) {
      if (sets[p].empty()) continue;
      const uint32_t id = static_cast<uint32_t>(patches.size());
      uint32_t seed = kNone;
      if (!regrow_whole(g, picker, sets[p], id, faces, verts, &seed)) {
        // Neither seed grows the whole set (it was never a whole regrowth,
        // or a merge trial's xy was restored): keep what grows from its
        // centre; grow_all below takes the rest.
        for (uint32_t f : faces) g.face_patch[f] = kNone;
        seed = picker.centre(sets[p]);
        if (seed == kNone) continue;
        g.grow(seed, id, faces, verts);
      }
      patches.push_back(faces);
      seed_of.push_back(seed);
    }
    const size_t centred = patches.size();
    grow_all(g, patches);
    for (size_t p = centred; p < patches.size(); ++p)
      seed_of.push_back(*std::min_element(patches[p].begin(), patches[p].end()));
    if (opt.solve_merge) {
      SolveMergeOptions so;
      so.tau = opt.tau;
      so.params = opt.solve;
      so.max_faces = opt.solve_max_faces;
      so.budget = opt.solve_budget;
      so.max_solved_share = opt.solve_max_share;
      so.min_fill = opt.merge_min_fill;
      const JoinRule can_join = [&](std::span<const uint32_t> a, std::span<const uint32_t> b) {
        if (!dr.active) return true;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (uint32_t f : a) DensityRule::extend(lo, hi, dr.at(f));
        for (uint32_t f : b) DensityRule::extend(lo, hi, dr.at(f));
        return !(lo <= hi && hi - lo > dr.limit);
      };
      if (solve_merge(mesh, opp, patches, g.xy, methods, so, can_join) > 0) out.solve = so.params;
    }
  } else {
    grow_all(g, patches, /*plain=*/true);
  }
  // Number patches by lowest face (grow_all seeds each at its lowest face).
  std::vector<uint32_t> order(patches.size()), rank(patches.size());
  std::vector<uint32_t> low(patches.size(), kNone);
  for (uint32_t p = 0; p < patches.size(); ++p)
    for (uint32_t f : patches[p]) low[p] = std::min(low[p], f);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return low[a] < low[b]; });
  uint32_t count = 0;
  for (uint32_t p : order)
    if (!patches[p].empty()) rank[p] = count++;
  out.patch_of_face.assign(nf, 0);
  for (uint32_t p = 0; p < patches.size(); ++p)
    for (uint32_t f : patches[p]) out.patch_of_face[f] = rank[p];
  out.patch_count = count;
  bool any_solve = false;
  for (uint8_t m : methods) any_solve = any_solve || m == uint8_t(LayoutMethod::solve);
  if (any_solve) {
    out.methods.assign(count, uint8_t(LayoutMethod::unfold));
    for (uint32_t p = 0; p < patches.size(); ++p)
      if (!patches[p].empty()) out.methods[rank[p]] = methods[p];
  }
  if (!seed_of.empty()) {
    out.seeds.assign(count, 0);
    bool all_lowest = true;
    for (uint32_t p = 0; p < patches.size(); ++p) {
      if (patches[p].empty()) continue;
      // A solved patch has no seed: its lowest face costs the fewest bits.
      if (any_solve && methods[p] == uint8_t(LayoutMethod::solve)) seed_of[p] = low[p];
      out.seeds[rank[p]] = seed_of[p];
      all_lowest = all_lowest && seed_of[p] == low[p];
    }
    if (all_lowest) out.seeds.clear();  // a 1.0 stream says the same in fewer bytes
  }
  out.encoder_xy = std::move(g.xy);
  out.status = layout_patches(mesh, out.patch_of_face, out.patch_count, out.corner_xy, out.seeds, out.methods,
                              out.solve);
  if (out.status == LayoutStatus::ok)
    out.report = measure_embedding(mesh, out.patch_of_face, out.patch_count, out.corner_xy, opt.tau);
  return out;
}

}  // namespace gltfwarp
