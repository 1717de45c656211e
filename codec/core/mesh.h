// Triangle meshes as the decoder sees them ("D" in DESIGN.md): the positions
// and faces that Draco decodes. Every stage of the codec works on this type.
#pragma once

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

}  // namespace gltfwarp
