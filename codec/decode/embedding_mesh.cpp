#include "codec/decode/embedding_mesh.h"

#include <cstring>
#include <span>
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
// Welds point_count points, whose coordinates `xyz(p, k)` gives, by exact
// bit equality. Indices past the points map to kInvalidVertex, which every
// consumer of the mesh rejects as bad_mesh.
template <typename Xyz>
TriMesh weld(size_t n, Xyz&& xyz, std::span<const uint32_t> triangles,
             std::vector<uint32_t>& point_to_vertex) {
  TriMesh mesh;
  point_to_vertex.assign(n, 0);
  // Open addressing over the position bits (linear probing, load <= 1/2):
  // the same vertices in the same order as a map, without a node per point.
  size_t cap = 16;
  while (cap < 2 * n) cap <<= 1;
  std::vector<uint32_t> slot(cap, UINT32_MAX);
  mesh.positions.reserve(3 * n);
  const KeyHash hash;
  for (size_t p = 0; p < n; ++p) {
    const float x = xyz(p, 0), y = xyz(p, 1), z = xyz(p, 2);
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
    mesh.indices[i] = triangles[i] < n ? point_to_vertex[triangles[i]] : kInvalidVertex;
  return mesh;
}

}  // namespace

TriMesh embedding_mesh(const VertexAttribute& positions, const std::vector<uint32_t>& triangles,
                       std::vector<uint32_t>& point_to_vertex) {
  return weld(
      positions.count(), [&](size_t p, int k) { return positions.get(p, k); }, triangles, point_to_vertex);
}

TriMesh embedding_mesh(std::span<const float> xyz, std::span<const uint32_t> triangles,
                       std::vector<uint32_t>& point_to_vertex) {
  return weld(
      xyz.size() / 3, [&](size_t p, int k) { return xyz[3 * p + size_t(k)]; }, triangles, point_to_vertex);
}

}  // namespace gltfwarp
