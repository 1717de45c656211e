// The shared layout replay (see layout.h for the normative rules). Growth in
// breadth-first rounds with unfolding and relaxation follows Sorkine &
// Cohen-Or, "Warped Textures for UV Mapping Encoding" (2001), section 3; the
// relaxation is a few steps of stress majorization (de Leeuw's SMACOF, 1977)
// restricted to the new vertex. Every decision the paper makes with a
// threshold was made by the encoder and is visible here only as membership.
//
// Linear time: one counting sort for vertex -> faces, one for patch -> faces,
// and per-vertex state reset by generation stamps instead of clears.
#include "codec/core/layout.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "codec/core/parallel.h"
#include "codec/core/topology.h"

namespace gltfwarp {

const char* to_string(LayoutStatus s) {
  switch (s) {
    case LayoutStatus::ok:
      return "ok";
    case LayoutStatus::bad_patch_id:
      return "bad patch id";
    case LayoutStatus::patch_order:
      return "patches not numbered by lowest face";
    case LayoutStatus::unreachable_face:
      return "a face of a patch is never reached";
    case LayoutStatus::bad_mesh:
      return "index out of range";
    case LayoutStatus::bad_seed:
      return "seed outside its patch";
    case LayoutStatus::bad_method:
      return "bad layout method";
    case LayoutStatus::not_disc:
      return "a solved patch is not a disc";
  }
  return "unknown";
}

void place_seed(const TriMesh& m, uint32_t face, Vec2 out[3]) {
  const uint32_t v0 = m.indices[3 * face], v1 = m.indices[3 * face + 1], v2 = m.indices[3 * face + 2];
  out[0] = {0.0, 0.0};
  const double l01s = length3_sq(m, v0, v1), l02s = length3_sq(m, v0, v2);
  const double l01 = std::sqrt(l01s), l02 = std::sqrt(l02s);
  out[1] = v1 == v0 ? out[0] : Vec2{l01, 0.0};
  if (v2 == v0) {
    out[2] = out[0];
  } else if (v2 == v1) {
    out[2] = out[1];
  } else if (v1 == v0) {
    out[2] = {l02, 0.0};
  } else if (l01 == 0) {
    out[2] = {0.0, l02};
  } else {
    const double l12s = length3_sq(m, v1, v2);
    const double x = (l01s + l02s - l12s) / (2.0 * l01);
    const double y2 = l02s - x * x;
    out[2] = {x, std::sqrt(y2 > 0 ? y2 : 0.0)};
  }
}

#if defined(__SSE2__)
// The same rule, two lanes at a time. Every lane computes the scalar
// expression of layout.h with the same operations in the same order (SSE2
// add, mul, div and sqrt round exactly as their scalar forms; no FMA), and
// the sums are still accumulated one term at a time in face order. An edge
// the relaxation skips adds +0.0 to sums that start at +0.0, which leaves
// them unchanged: such a sum is never -0.0 (x + y is -0.0 only when both are).
Vec2 place_vertex(std::span<const Unfolding> faces) {
  const size_t n = faces.size();
  const __m128d zero = _mm_setzero_pd();
  const __m128d neg_lo = _mm_set_pd(0.0, -0.0);  // flips the sign of lane 0
  __m128d s_xy = zero, m_xy = zero;              // (sx, sy), (mx, my)
  double sw = 0;
  for (const Unfolding& f : faces) {
    const __m128d A = _mm_loadu_pd(&f.a.x), B = _mm_loadu_pd(&f.b.x);
    const __m128d E = _mm_sub_pd(B, A);  // (ex, ey)
    __m128d U;
    if (f.lab2 > 0) {
      const double la2 = f.la * f.la;
      // (s, la^2 / lab2) = ((la^2 - lb^2 + lab2) / (2 lab2), la^2 / lab2)
      const __m128d q =
          _mm_div_pd(_mm_set_pd(la2, la2 - f.lb * f.lb + f.lab2), _mm_set_pd(f.lab2, 2.0 * f.lab2));
      const double s = _mm_cvtsd_f64(q);
      const double t2 = _mm_cvtsd_f64(_mm_unpackhi_pd(q, q)) - s * s;
      const double t = _mm_cvtsd_f64(_mm_sqrt_sd(zero, _mm_set_sd(t2 > 0 ? t2 : 0.0)));
      // (ux, uy) = (a.x + s ex - t ey, a.y + s ey + t ex)
      const __m128d base = _mm_add_pd(A, _mm_mul_pd(_mm_set1_pd(s), E));
      const __m128d perp = _mm_mul_pd(_mm_set1_pd(t), _mm_shuffle_pd(E, E, 1));  // (t ey, t ex)
      U = _mm_add_pd(base, _mm_xor_pd(perp, neg_lo));
    } else {
      U = _mm_div_pd(_mm_add_pd(A, B), _mm_set1_pd(2.0));
    }
    const __m128d E2 = _mm_mul_pd(E, E);
    const double d2 = _mm_cvtsd_f64(E2) + _mm_cvtsd_f64(_mm_unpackhi_pd(E2, E2));
    const double den = d2 + f.lab2;
    double e = 1.0;
    if (den > 0) {
      const __m128d r = _mm_sqrt_pd(_mm_set_pd(f.lab2, d2));  // (sqrt d2, sqrt lab2)
      e = 2.0 * _mm_cvtsd_f64(r) * _mm_cvtsd_f64(_mm_unpackhi_pd(r, r)) / den;
    }
    const double w = e * e;
    s_xy = _mm_add_pd(s_xy, _mm_mul_pd(_mm_set1_pd(w), U));
    sw += w;
    m_xy = _mm_add_pd(m_xy, U);
  }
  __m128d P =
      sw > 0 ? _mm_div_pd(s_xy, _mm_set1_pd(sw)) : _mm_div_pd(m_xy, _mm_set1_pd(static_cast<double>(n)));
  // The edge weights 1 / l^2 do not change between steps: computed once, the
  // same values as computing them in every step. Lane 0: edge to a, lane 1: to b.
  constexpr size_t kStackFaces = 16;
  double stack_w[2 * kStackFaces];
  std::vector<double> heap_w;
  double* inv_l2 = stack_w;
  if (n > kStackFaces) {
    heap_w.resize(2 * n);
    inv_l2 = heap_w.data();
  }
  for (size_t i = 0; i < n; ++i) {
    const __m128d L = _mm_set_pd(faces[i].lb, faces[i].la);
    _mm_storeu_pd(inv_l2 + 2 * i,
                  _mm_and_pd(_mm_div_pd(_mm_set1_pd(1.0), _mm_mul_pd(L, L)), _mm_cmpneq_pd(L, zero)));
  }
  for (int step = 0; step < kRelaxSteps; ++step) {
    const __m128d px = _mm_unpacklo_pd(P, P), py = _mm_unpackhi_pd(P, P);
    __m128d n_xy = zero;
    double nw = 0;
    for (size_t i = 0; i < n; ++i) {
      const Unfolding& f = faces[i];
      const __m128d A = _mm_loadu_pd(&f.a.x), B = _mm_loadu_pd(&f.b.x);
      const __m128d X = _mm_unpacklo_pd(A, B), Y = _mm_unpackhi_pd(A, B);  // (a.x, b.x), (a.y, b.y)
      const __m128d L = _mm_set_pd(f.lb, f.la);
      const __m128d dx = _mm_sub_pd(px, X), dy = _mm_sub_pd(py, Y);
      const __m128d r = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)));
      const __m128d used = _mm_and_pd(_mm_cmpneq_pd(L, zero), _mm_cmpneq_pd(r, zero));
      const __m128d g = _mm_div_pd(L, r);
      const __m128d w = _mm_and_pd(_mm_loadu_pd(inv_l2 + 2 * i), used);
      const __m128d tx = _mm_and_pd(_mm_mul_pd(w, _mm_add_pd(X, _mm_mul_pd(g, dx))), used);
      const __m128d ty = _mm_and_pd(_mm_mul_pd(w, _mm_add_pd(Y, _mm_mul_pd(g, dy))), used);
      n_xy = _mm_add_pd(n_xy, _mm_unpacklo_pd(tx, ty));  // edge to a
      nw += _mm_cvtsd_f64(w);
      n_xy = _mm_add_pd(n_xy, _mm_unpackhi_pd(tx, ty));  // edge to b
      nw += _mm_cvtsd_f64(_mm_unpackhi_pd(w, w));
    }
    if (nw > 0) P = _mm_div_pd(n_xy, _mm_set1_pd(nw));
  }
  Vec2 p;
  _mm_storeu_pd(&p.x, P);
  return p;
}

namespace {

inline __m128d select(__m128d mask, __m128d yes, __m128d no) {
  return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no));
}
inline __m128d lanes(const Unfolding& f0, const Unfolding& f1, double Unfolding::*m) {
  return _mm_set_pd(f1.*m, f0.*m);
}

// place_vertex for two vertices whose unfoldings do not depend on each other,
// lane 0 for f0 and lane 1 for f1: each lane runs the scalar rule of
// layout.h operation for operation (branches become selects, max(t2, 0)
// becomes maxpd, which also gives +0.0 for NaN and -0.0), and a lane past its
// own faces adds +0.0 to sums that start at +0.0, leaving them unchanged. The
// two dependency chains then run side by side instead of one after the other.
void place_two(std::span<const Unfolding> f0, std::span<const Unfolding> f1, Vec2& p0, Vec2& p1) {
  const size_t n0 = f0.size(), n1 = f1.size(), n = std::max(n0, n1);
  const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0), two = _mm_set1_pd(2.0);
  const __m128d all = _mm_castsi128_pd(_mm_set1_epi32(-1));
  auto active = [&](size_t i) {
    return _mm_and_pd(all, _mm_castsi128_pd(_mm_set_epi64x(i < n1 ? -1 : 0, i < n0 ? -1 : 0)));
  };
  __m128d sx = zero, sy = zero, sw = zero, mx = zero, my = zero;
  for (size_t i = 0; i < n; ++i) {
    const Unfolding& a = f0[i < n0 ? i : 0];
    const Unfolding& b = f1[i < n1 ? i : 0];
    const __m128d on = active(i);
    const __m128d ax = _mm_set_pd(b.a.x, a.a.x), ay = _mm_set_pd(b.a.y, a.a.y);
    const __m128d bx = _mm_set_pd(b.b.x, a.b.x), by = _mm_set_pd(b.b.y, a.b.y);
    const __m128d la = lanes(a, b, &Unfolding::la), lb = lanes(a, b, &Unfolding::lb);
    const __m128d lab2 = lanes(a, b, &Unfolding::lab2);
    const __m128d ex = _mm_sub_pd(bx, ax), ey = _mm_sub_pd(by, ay);
    const __m128d la2 = _mm_mul_pd(la, la);
    const __m128d s =
        _mm_div_pd(_mm_add_pd(_mm_sub_pd(la2, _mm_mul_pd(lb, lb)), lab2), _mm_mul_pd(two, lab2));
    const __m128d t2 = _mm_sub_pd(_mm_div_pd(la2, lab2), _mm_mul_pd(s, s));
    const __m128d t = _mm_sqrt_pd(_mm_max_pd(t2, zero));
    const __m128d unf = _mm_cmpgt_pd(lab2, zero);
    const __m128d ux = select(unf, _mm_sub_pd(_mm_add_pd(ax, _mm_mul_pd(s, ex)), _mm_mul_pd(t, ey)),
                              _mm_div_pd(_mm_add_pd(ax, bx), two));
    const __m128d uy = select(unf, _mm_add_pd(_mm_add_pd(ay, _mm_mul_pd(s, ey)), _mm_mul_pd(t, ex)),
                              _mm_div_pd(_mm_add_pd(ay, by), two));
    const __m128d d2 = _mm_add_pd(_mm_mul_pd(ex, ex), _mm_mul_pd(ey, ey));
    const __m128d den = _mm_add_pd(d2, lab2);
    const __m128d e =
        select(_mm_cmpgt_pd(den, zero),
               _mm_div_pd(_mm_mul_pd(_mm_mul_pd(two, _mm_sqrt_pd(d2)), _mm_sqrt_pd(lab2)), den), one);
    const __m128d w = _mm_mul_pd(e, e);
    sx = _mm_add_pd(sx, _mm_and_pd(on, _mm_mul_pd(w, ux)));
    sy = _mm_add_pd(sy, _mm_and_pd(on, _mm_mul_pd(w, uy)));
    sw = _mm_add_pd(sw, _mm_and_pd(on, w));
    mx = _mm_add_pd(mx, _mm_and_pd(on, ux));
    my = _mm_add_pd(my, _mm_and_pd(on, uy));
  }
  const __m128d weighted = _mm_cmpgt_pd(sw, zero);
  const __m128d count = _mm_set_pd(static_cast<double>(n1), static_cast<double>(n0));
  __m128d px = select(weighted, _mm_div_pd(sx, sw), _mm_div_pd(mx, count));
  __m128d py = select(weighted, _mm_div_pd(sy, sw), _mm_div_pd(my, count));
  for (int step = 0; step < kRelaxSteps; ++step) {
    __m128d nx = zero, ny = zero, nw = zero;
    for (size_t i = 0; i < n; ++i) {
      const Unfolding& a = f0[i < n0 ? i : 0];
      const Unfolding& b = f1[i < n1 ? i : 0];
      const __m128d on = active(i);
      for (int k = 0; k < 2; ++k) {
        const __m128d X = k == 0 ? _mm_set_pd(b.a.x, a.a.x) : _mm_set_pd(b.b.x, a.b.x);
        const __m128d Y = k == 0 ? _mm_set_pd(b.a.y, a.a.y) : _mm_set_pd(b.b.y, a.b.y);
        const __m128d l = k == 0 ? lanes(a, b, &Unfolding::la) : lanes(a, b, &Unfolding::lb);
        const __m128d nz = _mm_cmpneq_pd(l, zero);
        const __m128d w = _mm_and_pd(_mm_div_pd(one, _mm_mul_pd(l, l)), nz);
        const __m128d dx = _mm_sub_pd(px, X), dy = _mm_sub_pd(py, Y);
        const __m128d r = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)));
        const __m128d used = _mm_and_pd(on, _mm_and_pd(nz, _mm_cmpneq_pd(r, zero)));
        const __m128d g = _mm_div_pd(l, r);
        nx = _mm_add_pd(nx, _mm_and_pd(used, _mm_mul_pd(w, _mm_add_pd(X, _mm_mul_pd(g, dx)))));
        ny = _mm_add_pd(ny, _mm_and_pd(used, _mm_mul_pd(w, _mm_add_pd(Y, _mm_mul_pd(g, dy)))));
        nw = _mm_add_pd(nw, _mm_and_pd(used, w));
      }
    }
    const __m128d moved = _mm_cmpgt_pd(nw, zero);
    px = select(moved, _mm_div_pd(nx, nw), px);
    py = select(moved, _mm_div_pd(ny, nw), py);
  }
  double x[2], y[2];
  _mm_storeu_pd(x, px);
  _mm_storeu_pd(y, py);
  p0 = {x[0], y[0]};
  p1 = {x[1], y[1]};
}

}  // namespace
#else
Vec2 place_vertex(std::span<const Unfolding> faces) {
  double sx = 0, sy = 0, sw = 0, mx = 0, my = 0;
  for (const Unfolding& f : faces) {
    const double ex = f.b.x - f.a.x, ey = f.b.y - f.a.y;
    double ux, uy;
    if (f.lab2 > 0) {
      const double s = (f.la * f.la - f.lb * f.lb + f.lab2) / (2.0 * f.lab2);
      const double t2 = f.la * f.la / f.lab2 - s * s;
      const double t = std::sqrt(t2 > 0 ? t2 : 0.0);
      ux = f.a.x + s * ex - t * ey;
      uy = f.a.y + s * ey + t * ex;
    } else {
      ux = (f.a.x + f.b.x) / 2.0;
      uy = (f.a.y + f.b.y) / 2.0;
    }
    const double d2 = ex * ex + ey * ey;
    const double den = d2 + f.lab2;
    const double e = den > 0 ? 2.0 * std::sqrt(d2) * std::sqrt(f.lab2) / den : 1.0;
    const double w = e * e;
    sx += w * ux;
    sy += w * uy;
    sw += w;
    mx += ux;
    my += uy;
  }
  Vec2 p;
  if (sw > 0) {
    p = {sx / sw, sy / sw};
  } else {
    const double n = static_cast<double>(faces.size());
    p = {mx / n, my / n};
  }
  // The edge weights 1 / l^2 do not change between steps: computed once, the
  // same values as computing them in every step.
  constexpr size_t kStackFaces = 16;
  double stack_w[2 * kStackFaces];
  std::vector<double> heap_w;
  double* inv_l2 = stack_w;
  if (faces.size() > kStackFaces) {
    heap_w.resize(2 * faces.size());
    inv_l2 = heap_w.data();
  }
  for (size_t i = 0; i < faces.size(); ++i) {
    const double la = faces[i].la, lb = faces[i].lb;
    inv_l2[2 * i] = la != 0 ? 1.0 / (la * la) : 0.0;
    inv_l2[2 * i + 1] = lb != 0 ? 1.0 / (lb * lb) : 0.0;
  }
  for (int step = 0; step < kRelaxSteps; ++step) {
    double nx = 0, ny = 0, nw = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
      const Unfolding& f = faces[i];
      for (int k = 0; k < 2; ++k) {
        const Vec2 x = k == 0 ? f.a : f.b;
        const double l = k == 0 ? f.la : f.lb;
        const double dx = p.x - x.x, dy = p.y - x.y;
        const double r = std::sqrt(dx * dx + dy * dy);
        if (l == 0 || r == 0) continue;
        const double w = inv_l2[2 * i + k], g = l / r;
        nx += w * (x.x + g * dx);
        ny += w * (x.y + g * dy);
        nw += w;
      }
    }
    if (nw > 0) p = {nx / nw, ny / nw};
  }
  return p;
}

#endif

namespace {
// Positions of two candidates whose faces do not involve each other.
inline void place_pair(std::span<const Unfolding> f0, std::span<const Unfolding> f1, Vec2& p0, Vec2& p1) {
#if defined(__SSE2__)
  place_two(f0, f1, p0, p1);
#else
  p0 = place_vertex(f0);
  p1 = place_vertex(f1);
#endif
}
}  // namespace

void faces_by_patch(std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                    std::vector<uint32_t>& start, std::vector<uint32_t>& faces) {
  const size_t nf = patch_of_face.size();
  start.assign(size_t{patch_count} + 1, 0);
  for (size_t f = 0; f < nf; ++f) ++start[patch_of_face[f] + 1];
  for (uint32_t p = 0; p < patch_count; ++p) start[p + 1] += start[p];
  faces.resize(nf);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < nf; ++f) faces[fill[patch_of_face[f]]++] = uint32_t(f);
}

namespace {

// Face incidences grouped per vertex, and within a vertex sorted by (patch,
// face): the faces of v in patch p are one contiguous run, ascending. Filled
// by walking the faces patch by patch (pfaces order), so no sort is needed.
// Each entry is one corner of v and carries the face's other two vertices in
// the face's cyclic order starting at v, so the replay never goes back to the
// index buffer (a random access per face) to find them. A face naming v
// twice has two entries, one per corner, as it had one per listing.
struct Incidence {
  uint32_t patch, a, b;
};

// Per-vertex replay state side by side (one cache line access per vertex):
// placed == p + 1 marks the vertex placed in patch p; listed == round stamp
// marks it already in the next candidate list; [cursor, end) are its
// incidences not of an earlier patch.
struct VertexState {
  uint32_t placed = 0, listed = 0, cursor = 0, end = 0;
};

// Moves v's cursor past the runs of patches < p (patches are replayed in
// ascending order, so each entry is skipped at most once overall) and returns
// the end of v's run in patch p.
inline uint32_t run_of(VertexState& v, const Incidence* entries, uint32_t p, uint32_t& begin) {
  uint32_t i = v.cursor;
  const uint32_t end = v.end;
  while (i < end && entries[i].patch < p) ++i;
  v.cursor = i;
  begin = i;
  while (i < end && entries[i].patch == p) ++i;
  return i;
}

// The validated input of the replay, shared read-only by its ranges.
struct ReplayInput {
  const TriMesh& mesh;
  const std::vector<uint32_t>& poff;  // faces_by_patch
  const std::vector<uint32_t>& pfaces;
  std::span<const uint32_t> seeds;
  std::span<const uint8_t> methods;
  const SolveParams& solve;
};

// Patches [first, last) of the replay, with their own incidences and
// per-vertex state, so ranges run side by side without sharing a write.
template <typename Emit>
LayoutStatus replay_range(const ReplayInput& in, uint32_t first, uint32_t last, Emit& emit) {
  const TriMesh& mesh = in.mesh;
  const uint32_t nv = mesh.vertex_count();
  const uint32_t* idx = mesh.indices.data();
  const std::vector<uint32_t>& poff = in.poff;
  const std::vector<uint32_t>& pfaces = in.pfaces;
  const std::span<const uint32_t> seeds = in.seeds;
  const std::span<const uint8_t> methods = in.methods;
  const SolveParams& solve = in.solve;

  std::vector<VertexState> vs(nv);
  // Every entry is written below before it is read: no zero fill.
  const size_t range_corners = 3 * size_t{poff[last] - poff[first]};
  const std::unique_ptr<Incidence[]> entries_owner(new Incidence[range_corners]);
  Incidence* const entries = entries_owner.get();
  {
    for (uint32_t i = poff[first]; i < poff[last]; ++i)
      for (int k = 0; k < 3; ++k) ++vs[idx[3 * size_t{pfaces[i]} + k]].end;
    uint32_t sum = 0;
    for (VertexState& s : vs) {
      s.cursor = sum;  // used as the fill position, then reset to the start
      sum += s.end;
      s.end = sum;
    }
    for (uint32_t p = first; p < last; ++p)
      for (uint32_t i = poff[p]; i < poff[p + 1]; ++i) {
        const uint32_t* t = idx + 3 * size_t{pfaces[i]};
        entries[vs[t[0]].cursor++] = {p, t[1], t[2]};
        entries[vs[t[1]].cursor++] = {p, t[2], t[0]};
        entries[vs[t[2]].cursor++] = {p, t[0], t[1]};
      }
    uint32_t start = 0;
    for (VertexState& s : vs) {
      s.cursor = start;
      start = s.end;
    }
  }
  std::vector<Vec2> pos(nv);
  std::vector<uint32_t> fresh, list;
  std::vector<Unfolding> unf, unf2;
  std::vector<uint32_t> ab, ab2;
  uint32_t round_stamp = 0;
  SolveScratch solve_scratch;
  std::vector<Vec2> solve_pos;

  for (uint32_t p = first; p < last; ++p) {
    const uint32_t mark = p + 1;
    if (!methods.empty() && methods[p] == uint8_t(LayoutMethod::solve)) {
      const std::span<const uint32_t> pf(pfaces.data() + poff[p], poff[p + 1] - poff[p]);
      if (solve_pos.size() != nv) solve_pos.resize(nv);
      if (solve_patch(mesh, pf, solve, solve_pos, solve_scratch) != SolveStatus::ok)
        return LayoutStatus::not_disc;
      for (const uint32_t f : pf) {
        const Vec2 xy[3] = {solve_pos[idx[3 * f]], solve_pos[idx[3 * f + 1]], solve_pos[idx[3 * f + 2]]};
        emit(p, f, xy);
      }
      continue;
    }
    const uint32_t seed = seeds.empty() ? pfaces[poff[p]] : seeds[p];
    // The next patches start far from where this one's growth left the
    // caches: fetch their seed faces' indices, then vertex state (hints only).
    if (p + 2 < last)
      __builtin_prefetch(idx + 3 * size_t{seeds.empty() ? pfaces[poff[p + 2]] : seeds[p + 2]});
    if (p + 1 < last) {
      const uint32_t* t = idx + 3 * size_t{seeds.empty() ? pfaces[poff[p + 1]] : seeds[p + 1]};
      for (int k = 0; k < 3; ++k) {
        __builtin_prefetch(vs.data() + t[k]);
        __builtin_prefetch(mesh.positions.data() + 3 * size_t{t[k]});
      }
    }
    Vec2 sp[3];
    place_seed(mesh, seed, sp);
    fresh.clear();
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = idx[3 * seed + k];
      if (vs[v].placed == mark) continue;
      vs[v].placed = mark;
      pos[v] = sp[k];
      fresh.push_back(v);
    }
    for (;;) {
      // Candidates: every vertex that became eligible did so through a face
      // holding a vertex placed in the previous round. The faces (v, a, b) of
      // a fresh v: q = v (a, b placed), q = a (b, v placed), q = b (v, a placed);
      // v itself is placed, so only q = a and q = b can be new.
      ++round_stamp;
      list.clear();
      auto consider = [&](uint32_t q, uint32_t a, uint32_t b) {
        VertexState& s = vs[q];
        if (s.placed == mark || s.listed == round_stamp || q == a || q == b) return;
        if (vs[a].placed == mark && vs[b].placed == mark) {
          s.listed = round_stamp;
          list.push_back(q);
          // What placing q reads first (a hint only: the results do not depend on it).
          __builtin_prefetch(entries + s.cursor);
          __builtin_prefetch(mesh.positions.data() + 3 * size_t{q});
        }
      };
      for (uint32_t v : fresh) {
        uint32_t i;
        const uint32_t end = run_of(vs[v], entries, p, i);
        for (; i < end; ++i) {
          const Incidence& e = entries[i];
          consider(e.a, e.b, v);
          consider(e.b, v, e.a);
        }
      }
      if (list.empty()) break;
      std::sort(list.begin(), list.end());
      fresh.clear();
      // The faces that place q: those holding q exactly once whose other two
      // vertices are placed at q's turn. They depend on the placed marks
      // only, so q's list can be taken as soon as the candidate before it is
      // marked, before its position is known.
      auto faces_of = [&](uint32_t q, std::vector<uint32_t>& refs) {
        refs.clear();
        uint32_t i;
        const uint32_t end = run_of(vs[q], entries, p, i);
        for (; i < end; ++i) {
          const Incidence& e = entries[i];
          const uint32_t a = e.a, b = e.b;
          if (a == q || b == q) continue;  // q not exactly once (also skips the repeat listing)
          if (vs[a].placed != mark || vs[b].placed != mark) continue;
          refs.push_back(a);
          refs.push_back(b);
        }
      };
      auto unfold = [&](uint32_t q, const std::vector<uint32_t>& refs, std::vector<Unfolding>& out) {
        out.clear();
        for (size_t j = 0; j < refs.size(); j += 2)
          out.push_back(make_unfolding(mesh, q, refs[j], refs[j + 1], pos[refs[j]], pos[refs[j + 1]]));
      };
      size_t c = 0;
      bool have_next = false;  // ab holds list[c]'s faces already
      while (c < list.size()) {
        const uint32_t q = list[c];
        if (!have_next) faces_of(q, ab);
        have_next = false;
        vs[q].placed = mark;
        fresh.push_back(q);
        if (c + 1 < list.size()) {
          // The next candidate, with q marked as the sequential replay has it.
          const uint32_t q2 = list[c + 1];
          faces_of(q2, ab2);
          if (std::find(ab2.begin(), ab2.end(), q) == ab2.end()) {
            // Independent of q's position: both at once.
            unfold(q, ab, unf);
            unfold(q2, ab2, unf2);
            place_pair(unf, unf2, pos[q], pos[q2]);
            vs[q2].placed = mark;
            fresh.push_back(q2);
            c += 2;
            continue;
          }
          unfold(q, ab, unf);
          pos[q] = place_vertex(unf);
          ab.swap(ab2);
          have_next = true;
          ++c;
          continue;
        }
        unfold(q, ab, unf);
        pos[q] = place_vertex(unf);
        ++c;
      }
    }
    for (uint32_t i = poff[p]; i < poff[p + 1]; ++i) {
      const uint32_t f = pfaces[i];
      Vec2 xy[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = idx[3 * f + k];
        if (vs[v].placed != mark) return LayoutStatus::unreachable_face;
        xy[k] = pos[v];
      }
      emit(p, f, xy);
    }
  }
  return LayoutStatus::ok;
}

// Patches are laid out independently of each other (only their own marks,
// positions and incidences are read), so contiguous ranges of them replay on
// several threads, each with its own vertex state, and give the same bits as
// one thread. Below this many faces per thread a thread costs more than it saves.
constexpr uint32_t kFacesPerThread = 1u << 15;
constexpr uint32_t kRangesPerThread = 3;

// The replay (layout.h). emit(p, f, xy) receives each face of patch p, in
// ascending face order, once p is fully placed.
template <typename Emit>
LayoutStatus replay(const TriMesh& mesh, std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                    std::span<const uint32_t> seeds, std::span<const uint8_t> methods,
                    const SolveParams& solve, uint32_t max_threads, Emit&& emit) {
  if (!mesh_indices_valid(mesh)) return LayoutStatus::bad_mesh;
  const uint32_t nf = mesh.face_count();
  if (patch_of_face.size() != nf) return LayoutStatus::bad_patch_id;
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t p = patch_of_face[f];
    if (p >= patch_count) return LayoutStatus::bad_patch_id;
    if (p == next)
      ++next;
    else if (p > next)
      return LayoutStatus::patch_order;
  }
  if (next != patch_count) return LayoutStatus::bad_patch_id;
  if (!seeds.empty()) {
    if (seeds.size() != patch_count) return LayoutStatus::bad_seed;
    for (uint32_t p = 0; p < patch_count; ++p)
      if (seeds[p] >= nf || patch_of_face[seeds[p]] != p) return LayoutStatus::bad_seed;
  }
  if (!methods.empty()) {
    if (methods.size() != patch_count) return LayoutStatus::bad_method;
    for (const uint8_t m : methods)
      if (m > uint8_t(LayoutMethod::solve)) return LayoutStatus::bad_method;
  }
  std::vector<uint32_t> poff, pfaces;
  faces_by_patch(patch_of_face, patch_count, poff, pfaces);
  const ReplayInput input{mesh, poff, pfaces, seeds, methods, solve};
  const uint32_t threads = uint32_t(worker_count(std::min(nf / kFacesPerThread, patch_count), max_threads));
  if (threads == 1) return replay_range(input, 0, patch_count, emit);
  // Ranges of about equal face counts, cut at patch boundaries, a few per
  // thread and taken in turn: equal face counts are not equal work.
  const uint32_t ranges = std::min(patch_count, threads * kRangesPerThread);
  std::vector<uint32_t> cut(ranges + 1, patch_count);
  cut[0] = 0;
  for (uint32_t r = 1, p = 0; r < ranges; ++r) {
    const uint64_t target = uint64_t{nf} * r / ranges;
    while (p < patch_count && poff[p] < target) ++p;
    cut[r] = std::max(cut[r - 1], p);
  }
  std::vector<LayoutStatus> status(ranges, LayoutStatus::ok);
  run_in_parallel(ranges, threads, [&](size_t r, size_t) {
    if (cut[r] < cut[r + 1]) status[r] = replay_range(input, cut[r], cut[r + 1], emit);
  });
  // The first failing range holds the first failing patch: the error a
  // single thread reports.
  for (const LayoutStatus st : status)
    if (st != LayoutStatus::ok) return st;
  return LayoutStatus::ok;
}

}  // namespace

LayoutStatus layout_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                            uint32_t patch_count, std::vector<double>& corner_xy,
                            std::span<const uint32_t> seeds, std::span<const uint8_t> methods,
                            const SolveParams& solve, uint32_t threads) {
  corner_xy.clear();
  corner_xy.resize(size_t{mesh.face_count()} * 6, 0.0);
  return replay(mesh, patch_of_face, patch_count, seeds, methods, solve, threads,
                [&](uint32_t, uint32_t f, const Vec2 xy[3]) {
                  double* out = corner_xy.data() + 6 * size_t{f};
                  for (int k = 0; k < 3; ++k) {
                    out[2 * k] = xy[k].x;
                    out[2 * k + 1] = xy[k].y;
                  }
                });
}

LayoutStatus layout_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                            uint32_t patch_count, FaceSink sink, void* context,
                            std::span<const uint32_t> seeds, std::span<const uint8_t> methods,
                            const SolveParams& solve, uint32_t threads) {
  return replay(mesh, patch_of_face, patch_count, seeds, methods, solve, threads,
                [&](uint32_t p, uint32_t f, const Vec2 xy[3]) { sink(context, p, f, xy); });
}

}  // namespace gltfwarp
