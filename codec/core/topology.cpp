// Vertex -> face incidence and edge adjacency (a corner table in the sense of
// Rossignac, Safonova & Szymczak, "3D compression made simple: Edgebreaker on
// a corner-table", 2001), built with counting sorts in linear time.
#include "codec/core/topology.h"

namespace gltfwarp {

bool mesh_indices_valid(const TriMesh& mesh) {
  if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0) return false;
  const uint32_t n = mesh.vertex_count();
  for (uint32_t i : mesh.indices)
    if (i >= n) return false;
  return true;
}

VertexFaces build_vertex_faces(const TriMesh& mesh) {
  VertexFaces vf;
  const uint32_t nv = mesh.vertex_count();
  const size_t nc = mesh.indices.size();
  vf.offsets.assign(size_t{nv} + 1, 0);
  for (uint32_t v : mesh.indices) ++vf.offsets[v + 1];
  for (uint32_t v = 0; v < nv; ++v) vf.offsets[v + 1] += vf.offsets[v];
  vf.faces.resize(nc);
  std::vector<uint32_t> fill(vf.offsets.begin(), vf.offsets.end() - 1);
  // Corners in ascending order, so each vertex's faces come out ascending.
  for (size_t c = 0; c < nc; ++c) vf.faces[fill[mesh.indices[c]]++] = static_cast<uint32_t>(c / 3);
  return vf;
}

std::vector<uint32_t> build_opposite_corners(const TriMesh& mesh, const VertexFaces& vf) {
  const size_t nc = mesh.indices.size();
  std::vector<uint32_t> opp(nc, kNone);
  const uint32_t* idx = mesh.indices.data();
  // For every corner, scan the faces around the edge's lower vertex for other
  // faces holding the same edge. Valences are small, so this is linear in
  // practice; the count decides manifold (exactly one other) or seam.
  for (size_t c = 0; c < nc; ++c) {
    const uint32_t f = static_cast<uint32_t>(c / 3), k = static_cast<uint32_t>(c % 3);
    const uint32_t a = idx[3 * f + (k + 1) % 3], b = idx[3 * f + (k + 2) % 3];
    if (a == b) continue;
    const uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint32_t found = kNone, count = 0;
    uint32_t prev_face = kNone;
    for (uint32_t i = vf.offsets[lo]; i < vf.offsets[lo + 1]; ++i) {
      const uint32_t g = vf.faces[i];
      if (g == f || g == prev_face) continue;  // a face listed twice counts once
      prev_face = g;
      for (uint32_t j = 0; j < 3; ++j) {
        const uint32_t ga = idx[3 * g + (j + 1) % 3], gb = idx[3 * g + (j + 2) % 3];
        if ((ga == lo && gb == hi) || (ga == hi && gb == lo)) {
          ++count;
          found = 3 * g + j;
        }
      }
    }
    if (count == 1) opp[c] = found;
  }
  return opp;
}

}  // namespace gltfwarp
