// Copy patches for texel reuse (see twin_partition.h).
#include "codec/encode/partition/twin_partition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "codec/core/layout.h"
#include "codec/core/layout_report.h"
#include "codec/core/topology.h"
#include "codec/encode/partition/solve_merge.h"

namespace gltfwarp {
namespace {

// Copy patches are made only when they hold at least 1/kMinCopyShare of the
// faces. CesiumMilkTruck: its wheels (half their faces copies) gain; its body
// (7% of faces in copies) would pay 85 patches for 12.
constexpr size_t kMinCopyShare = 8;

// A face set partitioned on its own: patches as lists of (whole-mesh) faces,
// each with its seed face and layout method.
struct SubPartition {
  std::vector<std::vector<uint32_t>> patches;  // ascending faces
  std::vector<uint32_t> seeds;
  std::vector<uint8_t> methods;
  LayoutStatus status = LayoutStatus::ok;
};

// embed() on the faces `faces` (ascending) of `mesh` alone: the same vertex
// array, those faces' indices, and their slices of the per-face options.
SubPartition embed_faces(const TriMesh& mesh, std::span<const uint32_t> faces, const EmbedOptions& options) {
  SubPartition out;
  if (faces.empty()) return out;
  TriMesh sub;
  sub.positions = mesh.positions;
  sub.indices.reserve(faces.size() * 3);
  std::vector<double> density;
  std::vector<uint32_t> chart;
  for (uint32_t f : faces) {
    sub.indices.insert(sub.indices.end(), mesh.indices.begin() + 3 * f, mesh.indices.begin() + 3 * f + 3);
    if (!options.face_density.empty()) density.push_back(options.face_density[f]);
    if (!options.face_chart.empty()) chart.push_back(options.face_chart[f]);
  }
  EmbedOptions o = options;
  o.face_density = density;
  o.face_chart = chart;
  const Embedding e = embed(sub, o);
  out.status = e.status;
  if (e.status != LayoutStatus::ok) return out;
  out.patches.assign(e.patch_count, {});
  for (size_t i = 0; i < faces.size(); ++i) out.patches[e.patch_of_face[i]].push_back(faces[i]);
  out.seeds.resize(e.patch_count);
  out.methods.assign(e.patch_count, uint8_t(LayoutMethod::unfold));
  for (uint32_t p = 0; p < e.patch_count; ++p) {
    out.seeds[p] = e.seeds.empty() ? out.patches[p].front() : faces[e.seeds[p]];
    if (!e.methods.empty()) out.methods[p] = e.methods[p];
  }
  return out;
}

struct UvKey {
  std::array<uint32_t, 6> bits;  // the three UVs, sorted, as float bit patterns
  uint32_t face;
};

uint32_t float_bits(float v) {
  if (v == 0) v = 0;  // -0 and +0 are one UV
  uint32_t b;
  std::memcpy(&b, &v, 4);
  return b;
}

}  // namespace

FaceTwins find_face_twins(const TriMesh& mesh, std::span<const float> source_uv, double tolerance) {
  const uint32_t nf = mesh.face_count();
  FaceTwins t;
  t.primary.resize(nf);
  t.twin_corner.assign(size_t(nf) * 3, kNoTwin);
  for (uint32_t f = 0; f < nf; ++f) t.primary[f] = f;
  if (source_uv.size() != size_t(nf) * 6) return t;
  std::vector<UvKey> keys;
  keys.reserve(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    const float* uv = &source_uv[6 * size_t(f)];
    const double area =
        (double(uv[2]) - uv[0]) * (double(uv[5]) - uv[1]) - (double(uv[4]) - uv[0]) * (double(uv[3]) - uv[1]);
    if (!(area != 0) || !std::isfinite(area) || face_has_repeated_vertex(mesh, f)) continue;
    std::array<std::array<uint32_t, 2>, 3> c;
    for (int k = 0; k < 3; ++k) c[k] = {float_bits(uv[2 * k]), float_bits(uv[2 * k + 1])};
    std::sort(c.begin(), c.end());
    keys.push_back({{c[0][0], c[0][1], c[1][0], c[1][1], c[2][0], c[2][1]}, f});
  }
  // Equal keys side by side, lowest face first.
  std::sort(keys.begin(), keys.end(), [](const UvKey& a, const UvKey& b) {
    return a.bits != b.bits ? a.bits < b.bits : a.face < b.face;
  });
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j].bits == keys[i].bits) ++j;
    // Within a run the lowest face is the primary of every congruent face;
    // one that is not congruent to it stays its own (it may be the primary of none).
    const uint32_t g = keys[i].face;
    for (size_t k = i + 1; k < j; ++k) {
      const uint32_t f = keys[k].face;
      std::array<uint32_t, 3> map{};
      bool ok = true;
      for (int a = 0; a < 3 && ok; ++a) {
        int match = -1;
        for (int b = 0; b < 3; ++b)
          if (source_uv[6 * size_t(f) + 2 * a] == source_uv[6 * size_t(g) + 2 * b] &&
              source_uv[6 * size_t(f) + 2 * a + 1] == source_uv[6 * size_t(g) + 2 * b + 1])
            match = b;
        ok = match >= 0;
        if (ok) map[a] = 3 * g + uint32_t(match);
      }
      for (int a = 0; a < 3 && ok; ++a) {
        const uint32_t fa = mesh.indices[3 * f + a], fb = mesh.indices[3 * f + (a + 1) % 3];
        const uint32_t ga = mesh.indices[map[a]], gb = mesh.indices[map[(a + 1) % 3]];
        const double lf = length3(mesh, fa, fb), lg = length3(mesh, ga, gb);
        ok = std::abs(lf - lg) <= tolerance * std::max(lf, lg);
      }
      if (!ok) continue;
      t.primary[f] = g;
      for (int a = 0; a < 3; ++a) t.twin_corner[3 * size_t(f) + a] = map[a];
      ++t.copies;
    }
    i = j;
  }
  return t;
}

TwinEmbedding embed_with_twins(const TriMesh& mesh, std::span<const float> source_uv,
                               const EmbedOptions& options, uint32_t min_copies) {
  TwinEmbedding out;
  const uint32_t nf = mesh.face_count();
  const FaceTwins twins = find_face_twins(mesh, source_uv);
  auto plain = [&] {
    out.embedding = embed(mesh, options);
    out.reuse_of.assign(out.embedding.patch_count, -1);
    out.twin_corner.assign(size_t(nf) * 3, kNoTwin);
    out.copy_faces = 0;
    return out;
  };
  if (twins.copies < std::max<uint32_t>(min_copies, 1) || !mesh_indices_valid(mesh)) return plain();

  std::vector<uint32_t> primaries;
  std::vector<std::vector<uint32_t>> copies_of(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    if (twins.primary[f] == f)
      primaries.push_back(f);
    else
      copies_of[twins.primary[f]].push_back(f);
  }
  const SubPartition first = embed_faces(mesh, primaries, options);
  if (first.status != LayoutStatus::ok) return plain();

  const VertexFaces vf = build_vertex_faces(mesh);
  const std::vector<uint32_t> opposite = build_opposite_corners(mesh, vf);

  // Copy patches: per primary patch, the connected sets of its faces'
  // copies that map one to one (faces and vertices) onto it.
  struct Copy {
    std::vector<uint32_t> faces;  // ascending
    uint32_t of = 0;              // index into first.patches
    uint32_t seed = 0;
  };
  std::vector<Copy> copies;
  std::vector<uint8_t> in_set(nf, 0), taken(nf, 0);
  std::vector<uint32_t> vertex_map(mesh.vertex_count(), kNoTwin), vertex_back(mesh.vertex_count(), kNoTwin);
  std::vector<uint32_t> leftover;
  for (uint32_t a = 0; a < first.patches.size(); ++a) {
    const auto& patch = first.patches[a];
    std::vector<uint32_t> set;
    for (uint32_t g : patch)
      for (uint32_t c : copies_of[g]) set.push_back(c), in_set[c] = 1;
    for (uint32_t start : set) {
      if (taken[start]) continue;
      std::vector<uint32_t> comp = {start};
      taken[start] = 1;
      for (size_t i = 0; i < comp.size(); ++i)
        for (int k = 0; k < 3; ++k) {
          const uint32_t o = opposite[3 * size_t(comp[i]) + k];
          if (o == kNone) continue;
          const uint32_t n = o / 3;
          if (in_set[n] && !taken[n]) taken[n] = 1, comp.push_back(n);
        }
      std::sort(comp.begin(), comp.end());
      // One to one: as many faces as the patch, distinct primaries, and a
      // vertex map that is a bijection.
      bool ok = comp.size() == patch.size();
      std::vector<uint32_t> touched;
      if (ok) {
        std::vector<uint32_t> prim_of;
        for (uint32_t c : comp) prim_of.push_back(twins.primary[c]);
        std::sort(prim_of.begin(), prim_of.end());
        ok = std::adjacent_find(prim_of.begin(), prim_of.end()) == prim_of.end();
      }
      for (size_t i = 0; ok && i < comp.size(); ++i)
        for (int k = 0; k < 3 && ok; ++k) {
          const uint32_t v = mesh.indices[3 * size_t(comp[i]) + k];
          const uint32_t w = mesh.indices[twins.twin_corner[3 * size_t(comp[i]) + k]];
          if (vertex_map[v] == kNoTwin && vertex_back[w] == kNoTwin) {
            vertex_map[v] = w, vertex_back[w] = v;
            touched.push_back(v);
          } else {
            ok = vertex_map[v] == w && vertex_back[w] == v;
          }
        }
      for (uint32_t v : touched) vertex_back[vertex_map[v]] = kNoTwin, vertex_map[v] = kNoTwin;
      if (!ok) {
        leftover.insert(leftover.end(), comp.begin(), comp.end());
        continue;
      }
      Copy cp;
      cp.of = a;
      cp.seed = comp.front();
      for (uint32_t c : comp)
        if (twins.primary[c] == first.seeds[a]) cp.seed = c;
      cp.faces = std::move(comp);
      copies.push_back(std::move(cp));
    }
    for (uint32_t c : set) in_set[c] = 0;
  }

  // Assemble and lay out. Copy patches that do not replay well go back to the
  // leftovers, and the whole is assembled once more: each patch's replay
  // depends on its own faces alone, so the second round keeps every copy.
  for (;;) {
    std::sort(leftover.begin(), leftover.end());
    const SubPartition rest = embed_faces(mesh, leftover, options);
    if (rest.status != LayoutStatus::ok) return plain();
    // Every patch as (faces, seed, method, reused entry or -1), then numbered by lowest face.
    struct Entry {
      const std::vector<uint32_t>* faces;
      uint32_t seed;
      uint8_t method;
      int32_t reuse;  // entry index of the primary patch, or -1
      int32_t copy;   // index into copies, or -1
    };
    std::vector<Entry> entries;
    for (uint32_t a = 0; a < first.patches.size(); ++a)
      entries.push_back({&first.patches[a], first.seeds[a], first.methods[a], -1, -1});
    for (size_t i = 0; i < copies.size(); ++i)
      entries.push_back(
          {&copies[i].faces, copies[i].seed, first.methods[copies[i].of], int32_t(copies[i].of), int32_t(i)});
    for (uint32_t p = 0; p < rest.patches.size(); ++p)
      entries.push_back({&rest.patches[p], rest.seeds[p], rest.methods[p], -1, -1});
    std::vector<uint32_t> order(entries.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](uint32_t x, uint32_t y) { return entries[x].faces->front() < entries[y].faces->front(); });
    std::vector<uint32_t> id_of(entries.size());
    for (uint32_t i = 0; i < order.size(); ++i) id_of[order[i]] = i;

    Embedding& e = out.embedding;
    e = Embedding{};
    e.patch_count = uint32_t(entries.size());
    e.patch_of_face.assign(nf, 0);
    e.seeds.assign(e.patch_count, 0);
    e.methods.assign(e.patch_count, uint8_t(LayoutMethod::unfold));
    e.solve = options.solve;
    out.reuse_of.assign(e.patch_count, -1);
    bool any_seed = false, any_method = false;
    for (size_t i = 0; i < entries.size(); ++i) {
      const uint32_t id = id_of[i];
      for (uint32_t f : *entries[i].faces) e.patch_of_face[f] = id;
      e.seeds[id] = entries[i].seed;
      e.methods[id] = entries[i].method;
      any_seed = any_seed || entries[i].seed != entries[i].faces->front();
      any_method = any_method || entries[i].method != uint8_t(LayoutMethod::unfold);
      if (entries[i].reuse >= 0) out.reuse_of[id] = int32_t(id_of[size_t(entries[i].reuse)]);
    }
    if (!any_seed) e.seeds.clear();
    if (!any_method) e.methods.clear();
    e.status = layout_patches(mesh, e.patch_of_face, e.patch_count, e.corner_xy, e.seeds, e.methods, e.solve);
    if (e.status != LayoutStatus::ok) return plain();

    // Copies whose own replay is not a valid patch go to the leftovers.
    bool moved = false;
    for (size_t i = 0; i < copies.size();) {
      if (!solved_patch_acceptable(mesh, copies[i].faces, e.corner_xy, options.tau)) {
        leftover.insert(leftover.end(), copies[i].faces.begin(), copies[i].faces.end());
        copies.erase(copies.begin() + std::ptrdiff_t(i));
        moved = true;
        continue;
      }
      ++i;
    }
    if (moved) continue;

    // Splitting the mesh into primaries, copies and the rest costs seams;
    // few copies do not pay for them.
    size_t copy_faces = 0;
    for (const Copy& cp : copies) copy_faces += cp.faces.size();
    if (copy_faces * kMinCopyShare < nf) return plain();
    out.twin_corner.assign(size_t(nf) * 3, kNoTwin);
    out.copy_faces = 0;
    for (const Copy& cp : copies) {
      out.copy_faces += uint32_t(cp.faces.size());
      for (uint32_t f : cp.faces)
        for (int k = 0; k < 3; ++k) out.twin_corner[3 * size_t(f) + k] = twins.twin_corner[3 * size_t(f) + k];
    }
    e.report = measure_embedding(mesh, e.patch_of_face, e.patch_count, e.corner_xy, options.tau);
    return out;
  }
}

}  // namespace gltfwarp
