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
#include <vector>

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
struct PatchIncidence {
  struct Entry {
    uint32_t patch, face;
  };
  std::vector<uint32_t> offsets;  // vertex_count + 1
  std::vector<Entry> entries;     // 3 * face_count, (patch, face) side by side
  std::vector<uint32_t> cursor;   // per vertex: first entry not of an earlier patch
};

// Moves v's cursor past the runs of patches < p (patches are replayed in
// ascending order, so each entry is skipped at most once overall) and returns
// the end of v's run in patch p.
inline uint32_t run_of(PatchIncidence& pi, uint32_t v, uint32_t p, uint32_t& begin) {
  uint32_t i = pi.cursor[v];
  const uint32_t end = pi.offsets[v + 1];
  while (i < end && pi.entries[i].patch < p) ++i;
  pi.cursor[v] = i;
  begin = i;
  while (i < end && pi.entries[i].patch == p) ++i;
  return i;
}

// The replay (layout.h). emit(p, f, xy) receives each face of patch p, in
// ascending face order, once p is fully placed.
template <typename Emit>
LayoutStatus replay(const TriMesh& mesh, std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                    std::span<const uint32_t> seeds, std::span<const uint8_t> methods,
                    const SolveParams& solve, Emit&& emit) {
  if (!mesh_indices_valid(mesh)) return LayoutStatus::bad_mesh;
  const uint32_t nf = mesh.face_count(), nv = mesh.vertex_count();
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
  const uint32_t* idx = mesh.indices.data();

  std::vector<uint32_t> poff, pfaces;
  faces_by_patch(patch_of_face, patch_count, poff, pfaces);
  PatchIncidence inc;
  {
    const size_t nc = size_t{nf} * 3;
    inc.offsets.assign(size_t{nv} + 1, 0);
    for (size_t c = 0; c < nc; ++c) ++inc.offsets[idx[c] + 1];
    for (uint32_t v = 0; v < nv; ++v) inc.offsets[v + 1] += inc.offsets[v];
    inc.entries.resize(nc);
    inc.cursor.assign(inc.offsets.begin(), inc.offsets.end() - 1);
    std::vector<uint32_t>& fill = inc.cursor;  // restored below
    for (uint32_t p = 0; p < patch_count; ++p)
      for (uint32_t i = poff[p]; i < poff[p + 1]; ++i) {
        const uint32_t f = pfaces[i];
        for (int k = 0; k < 3; ++k) {
          const uint32_t e = fill[idx[3 * f + k]]++;
          inc.entries[e] = {p, f};
        }
      }
    std::copy(inc.offsets.begin(), inc.offsets.end() - 1, inc.cursor.begin());
  }

  // placed[v] == p + 1 marks v placed in patch p; listed[v] == round stamp
  // marks v already in the next candidate list.
  std::vector<uint32_t> placed(nv, 0), listed(nv, 0);
  std::vector<Vec2> pos(nv);
  std::vector<uint32_t> fresh, list;
  std::vector<Unfolding> unf;
  uint32_t round_stamp = 0;
  SolveScratch solve_scratch;

  for (uint32_t p = 0; p < patch_count; ++p) {
    const uint32_t mark = p + 1;
    if (!methods.empty() && methods[p] == uint8_t(LayoutMethod::solve)) {
      const std::span<const uint32_t> pf(pfaces.data() + poff[p], poff[p + 1] - poff[p]);
      if (solve_patch(mesh, pf, solve, pos, solve_scratch) != SolveStatus::ok) return LayoutStatus::not_disc;
      for (const uint32_t f : pf) {
        const Vec2 xy[3] = {pos[idx[3 * f]], pos[idx[3 * f + 1]], pos[idx[3 * f + 2]]};
        emit(p, f, xy);
      }
      continue;
    }
    const uint32_t seed = seeds.empty() ? pfaces[poff[p]] : seeds[p];
    Vec2 sp[3];
    place_seed(mesh, seed, sp);
    fresh.clear();
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = idx[3 * seed + k];
      if (placed[v] == mark) continue;
      placed[v] = mark;
      pos[v] = sp[k];
      fresh.push_back(v);
    }
    for (;;) {
      // Candidates: every vertex that became eligible did so through a face
      // holding a vertex placed in the previous round.
      ++round_stamp;
      list.clear();
      for (uint32_t v : fresh) {
        uint32_t i;
        const uint32_t end = run_of(inc, v, p, i);
        for (; i < end; ++i) {
          const uint32_t* t = idx + 3 * inc.entries[i].face;
          for (int k = 0; k < 3; ++k) {
            const uint32_t q = t[k], a = t[(k + 1) % 3], b = t[(k + 2) % 3];
            if (placed[q] == mark || listed[q] == round_stamp || q == a || q == b) continue;
            if (placed[a] == mark && placed[b] == mark) {
              listed[q] = round_stamp;
              list.push_back(q);
            }
          }
        }
      }
      if (list.empty()) break;
      std::sort(list.begin(), list.end());
      fresh.clear();
      for (uint32_t q : list) {
        unf.clear();
        uint32_t i;
        const uint32_t end = run_of(inc, q, p, i);
        for (; i < end; ++i) {
          const uint32_t* t = idx + 3 * inc.entries[i].face;
          const uint32_t k = t[0] == q ? 0 : (t[1] == q ? 1 : 2);
          const uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
          if (a == q || b == q) continue;  // q not exactly once (also skips the repeat listing)
          if (placed[a] != mark || placed[b] != mark) continue;
          unf.push_back(make_unfolding(mesh, q, a, b, pos[a], pos[b]));
        }
        pos[q] = place_vertex(unf);
        placed[q] = mark;
        fresh.push_back(q);
      }
    }
    for (uint32_t i = poff[p]; i < poff[p + 1]; ++i) {
      const uint32_t f = pfaces[i];
      Vec2 xy[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = idx[3 * f + k];
        if (placed[v] != mark) return LayoutStatus::unreachable_face;
        xy[k] = pos[v];
      }
      emit(p, f, xy);
    }
  }
  return LayoutStatus::ok;
}

}  // namespace

LayoutStatus layout_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                            uint32_t patch_count, std::vector<double>& corner_xy,
                            std::span<const uint32_t> seeds, std::span<const uint8_t> methods,
                            const SolveParams& solve) {
  corner_xy.clear();
  corner_xy.resize(size_t{mesh.face_count()} * 6, 0.0);
  return replay(mesh, patch_of_face, patch_count, seeds, methods, solve,
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
                            const SolveParams& solve) {
  return replay(mesh, patch_of_face, patch_count, seeds, methods, solve,
                [&](uint32_t p, uint32_t f, const Vec2 xy[3]) { sink(context, p, f, xy); });
}

}  // namespace gltfwarp
