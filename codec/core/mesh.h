// Triangle meshes as the decoder sees them ("D" in DESIGN.md): the positions
// and faces that Draco decodes. Every stage of the codec works on this type.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace gltfwarp {

struct TriMesh {
  std::vector<float> positions;   // x, y, z per vertex
  std::vector<uint32_t> indices;  // three vertex ids per face, counter-clockwise

  uint32_t vertex_count() const { return static_cast<uint32_t>(positions.size() / 3); }
  uint32_t face_count() const { return static_cast<uint32_t>(indices.size() / 3); }
};

// Corner c = 3 * face + k (k in 0..2) names vertex indices[c] as seen from
// that face. Per-corner data (UVs, patch-local positions) is indexed by corner.
inline uint32_t corner_of(uint32_t face, uint32_t k) { return 3 * face + k; }

// The 3D area of the triangle of vertices v[0], v[1], v[2], from x, y, z per
// vertex in `xyz` (TriMesh::positions, or a glTF primitive's POSITION).
inline double triangle_area3(const float* xyz, const uint32_t v[3]) {
  double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = double(xyz[3 * size_t(v[1]) + k]) - double(xyz[3 * size_t(v[0]) + k]);
    e2[k] = double(xyz[3 * size_t(v[2]) + k]) - double(xyz[3 * size_t(v[0]) + k]);
  }
  const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
  return 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
}

}  // namespace gltfwarp
