#include "codec/encode/cut_primitive.h"

#include <algorithm>

namespace gltfwarp {

PrimitiveGeometry part_geometry(const PrimitiveGeometry& geom, std::span<const uint32_t> part_of_face,
                                uint32_t part) {
  PrimitiveGeometry out;
  std::vector<uint32_t> new_id(geom.vertex_count(), UINT32_MAX);
  std::vector<uint32_t> kept;
  for (size_t f = 0; f < part_of_face.size(); ++f) {
    if (part_of_face[f] != part) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = geom.triangles[3 * f + k];
      if (new_id[v] == UINT32_MAX) {
        new_id[v] = uint32_t(kept.size());
        kept.push_back(v);
      }
      out.triangles.push_back(new_id[v]);
    }
  }
  for (const VertexAttribute& a : geom.attributes) {
    VertexAttribute b;
    b.semantic = a.semantic;
    b.component_type = a.component_type;
    b.components = a.components;
    b.normalized = a.normalized;
    const size_t size = a.element_size();
    b.data.resize(kept.size() * size);
    for (size_t i = 0; i < kept.size(); ++i)
      std::copy_n(a.data.data() + kept[i] * size, size, b.data.data() + i * size);
    out.attributes.push_back(std::move(b));
  }
  return out;
}

std::vector<int> cut_primitive(tinygltf::Model& model, int mesh, int primitive, const PrimitiveGeometry& geom,
                               std::span<const uint32_t> part_of_face, uint32_t part_count,
                               std::vector<int>& replaced) {
  std::vector<int> appended;
  const tinygltf::Primitive source = model.meshes[mesh].primitives[primitive];
  for (uint32_t part = 1; part < part_count; ++part) {
    tinygltf::Primitive copy = source;
    std::vector<int> shared;  // the source's accessors, superseded below
    write_primitive_plain(model, copy, part_geometry(geom, part_of_face, part), shared);
    model.meshes[mesh].primitives.push_back(std::move(copy));
    appended.push_back(int(model.meshes[mesh].primitives.size() - 1));
  }
  write_primitive_plain(model, model.meshes[mesh].primitives[primitive], part_geometry(geom, part_of_face, 0),
                        replaced);
  return appended;
}

}  // namespace gltfwarp
