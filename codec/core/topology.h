// Connectivity of a TriMesh, derived from its index buffer alone: the
// vertex -> faces incidence (CSR) and the face adjacency across edges. Both
// the shared replay (layout) and the partition (embed) build on it.
//
// Built in linear time with counting sorts; no hashing. Faces of a vertex are
// listed in ascending face id (the replay's order depends on it).
#pragma once

#include <cstdint>
#include <vector>

#include "codec/core/mesh.h"

namespace gltfwarp {

inline constexpr uint32_t kNone = 0xffffffffu;

// faces[offsets[v] .. offsets[v+1]) are the faces incident to vertex v, in
// ascending order. A face that names v twice is listed twice.
struct VertexFaces {
  std::vector<uint32_t> offsets;  // vertex_count + 1 entries
  std::vector<uint32_t> faces;    // 3 * face_count entries
};

// Requires every index < vertex_count (see mesh_indices_valid).
VertexFaces build_vertex_faces(const TriMesh& mesh);

// True when the buffers are whole and every index names a vertex.
bool mesh_indices_valid(const TriMesh& mesh);

// opposite[c] is the corner across the edge opposite corner c (the edge from
// vertex indices[next(c)] to indices[prev(c)]), or kNone when that edge is a
// boundary, is shared by three or more faces (non-manifold edges become
// seams), or is degenerate (both ends the same vertex). Two faces sharing an
// edge are adjacent regardless of their relative orientation.
std::vector<uint32_t> build_opposite_corners(const TriMesh& mesh, const VertexFaces& vf);

// True when the face names the same vertex twice.
inline bool face_has_repeated_vertex(const TriMesh& m, uint32_t f) {
  const uint32_t* v = &m.indices[3 * f];
  return v[0] == v[1] || v[1] == v[2] || v[0] == v[2];
}

}  // namespace gltfwarp
