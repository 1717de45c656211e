#include "codec/decode/embedding_mesh.h"

#include <cstring>
#include <vector>

namespace gltfwarp {

namespace {
struct Key {
  uint32_t x, y, z;
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + k.z * 0x94D049BB133111EBull;
    return static_cast<size_t>(h ^ (h >> 32));
  }
};
uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
}  // namespace

TriMesh embedding_mesh(const VertexAttribute& positions, const std::vector<uint32_t>& triangles,
                       std::vector<uint32_t>& point_to_vertex) {
  TriMesh mesh;
  const size_t n = positions.count();
  point_to_vertex.assign(n, 0);
  // Open addressing over the position bits (linear probing, load <= 1/2):
  // the same vertices in the same order as a map, without a node per point.
  size_t cap = 16;
  while (cap < 2 * n) cap <<= 1;
  std::vector<uint32_t> slot(cap, UINT32_MAX);
  mesh.positions.reserve(3 * n);
  const KeyHash hash;
  for (size_t p = 0; p < n; ++p) {
    const float x = positions.get(p, 0), y = positions.get(p, 1), z = positions.get(p, 2);
    const Key k{bits(x), bits(y), bits(z)};
    for (size_t i = hash(k) & (cap - 1);; i = (i + 1) & (cap - 1)) {
      const uint32_t v = slot[i];
      if (v == UINT32_MAX) {
        slot[i] = mesh.vertex_count();
        mesh.positions.insert(mesh.positions.end(), {x, y, z});
        point_to_vertex[p] = slot[i];
        break;
      }
      const float* q = &mesh.positions[3 * size_t{v}];
      if (Key{bits(q[0]), bits(q[1]), bits(q[2])} == k) {
        point_to_vertex[p] = v;
        break;
      }
    }
  }
  mesh.indices.resize(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i)
    mesh.indices[i] = triangles[i] < n ? point_to_vertex[triangles[i]] : 0;
  return mesh;
}

}  // namespace gltfwarp
