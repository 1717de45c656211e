#include "codec/encode/partition/source_charts.h"

#include <numeric>

#include "codec/core/topology.h"

namespace gltfwarp {

std::vector<uint32_t> source_charts(const TriMesh& mesh, std::span<const float> source_uv,
                                    const SeamTest& seamless) {
  const uint32_t nf = mesh.face_count();
  if (source_uv.size() != size_t{nf} * 6) return std::vector<uint32_t>(nf, 0);
  const VertexFaces vf = build_vertex_faces(mesh);
  const std::vector<uint32_t> opp = build_opposite_corners(mesh, vf);
  std::vector<uint32_t> parent(nf);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // The source UV of face f at vertex v (v is a corner of f).
  auto uv_at = [&](uint32_t f, uint32_t v) {
    const uint32_t* t = &mesh.indices[3 * size_t{f}];
    const size_t c = 3 * size_t{f} + (t[0] == v ? 0 : t[1] == v ? 1 : 2);
    return Uv{source_uv[2 * c], source_uv[2 * c + 1]};
  };
  for (size_t c = 0; c < opp.size(); ++c) {
    const uint32_t o = opp[c];
    if (o == kNone || o < c) continue;
    const uint32_t f = uint32_t(c / 3), g = o / 3;
    const uint32_t k = uint32_t(c % 3);
    const uint32_t va = mesh.indices[3 * size_t{f} + (k + 1) % 3],
                   vb = mesh.indices[3 * size_t{f} + (k + 2) % 3];
    const Uv fa = uv_at(f, va), fb = uv_at(f, vb), ga = uv_at(g, va), gb = uv_at(g, vb);
    if ((fa == ga && fb == gb) || (seamless && seamless(fa, fb, ga, gb))) {
      const uint32_t rf = find(f), rg = find(g);
      if (rf != rg) parent[std::max(rf, rg)] = std::min(rf, rg);
    }
  }
  // Roots are each chart's lowest face (unions keep the smaller root).
  std::vector<uint32_t> chart(nf), id_of_root(nf, kNone);
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t r = find(f);
    if (id_of_root[r] == kNone) id_of_root[r] = next++;
    chart[f] = id_of_root[r];
  }
  return chart;
}

}  // namespace gltfwarp
