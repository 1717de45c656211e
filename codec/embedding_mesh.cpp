#include "codec/embedding_mesh.h"

#include <cstring>
#include <unordered_map>

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
  std::unordered_map<Key, uint32_t, KeyHash> seen;
  seen.reserve(n);
  for (size_t p = 0; p < n; ++p) {
    const float x = positions.get(p, 0), y = positions.get(p, 1), z = positions.get(p, 2);
    auto [it, inserted] = seen.emplace(Key{bits(x), bits(y), bits(z)}, mesh.vertex_count());
    if (inserted) mesh.positions.insert(mesh.positions.end(), {x, y, z});
    point_to_vertex[p] = it->second;
  }
  mesh.indices.resize(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i)
    mesh.indices[i] = triangles[i] < n ? point_to_vertex[triangles[i]] : 0;
  return mesh;
}

}  // namespace gltfwarp
