// Decoder pipeline: Draco -> geometry; our bitstream -> per-corner UVs via
// decode_uvs (the very function the encoder used); vertices split where a
// point's corners got different UVs; plain accessors out.
#include "codec/decode/decoder.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>

#include "codec/decode/embedding_mesh.h"
#include "codec/decode/implicit_uv_primitive.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {
namespace {

// Draco quantizes float WEIGHTS_n independently, so their sum drifts from 1;
// glTF requires it to be 1, so scale each vertex's weights back.
void renormalize_weights(PrimitiveGeometry& geom) {
  std::vector<VertexAttribute*> sets;
  for (auto& a : geom.attributes)
    if (a.semantic.rfind("WEIGHTS_", 0) == 0 && a.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT)
      sets.push_back(&a);
  if (sets.empty()) return;
  for (size_t v = 0; v < geom.vertex_count(); ++v) {
    double sum = 0;
    for (auto* a : sets)
      for (int i = 0; i < a->components; ++i) sum += a->get(v, i);
    if (!(sum > 0)) continue;
    for (auto* a : sets)
      for (int i = 0; i < a->components; ++i) {
        const float w = static_cast<float>(a->get(v, i) / sum);
        std::memcpy(a->data.data() + (v * a->components + i) * 4, &w, 4);
      }
  }
}

// write_primitive_plain appends the decoded arrays to buffer 0; make room for
// them at once (growing geometrically) instead of through repeated
// reallocations of a buffer that reaches tens of megabytes on large meshes.
void reserve_plain_bytes(tinygltf::Model& model, const PrimitiveGeometry& geom) {
  if (model.buffers.empty()) return;
  size_t bytes = geom.triangles.size() * 4 + 4;
  for (const auto& a : geom.attributes) bytes += a.data.size() + 4;
  auto& buf = model.buffers[0].data;
  if (buf.capacity() - buf.size() < bytes) buf.reserve(std::max(buf.size() + bytes, 2 * buf.capacity()));
}

}  // namespace

std::string decode_model(tinygltf::Model& model, const DecodeOptions& options, DecodeReport& report) {
  std::vector<int> replaced;
  for (size_t mi = 0; mi < model.meshes.size(); ++mi) {
    auto& mesh = model.meshes[mi];
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      auto& prim = mesh.primitives[pi];
      const bool draco = prim.extensions.count(kDracoExtension) > 0;
      const bool ours = prim.extensions.count(ext::kName) > 0;
      if (!draco && !ours) continue;
      const std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) + ": ";
      PrimitiveGeometry geom;
      std::string err = read_primitive(model, prim, geom);
      if (!err.empty()) return where + err;
      if (draco) renormalize_weights(geom);
      if (ours) {
        err = rebuild_texcoords(model, prim, geom);
        if (!err.empty()) return where + err;
        prim.extensions.erase(ext::kName);
        report.uv_maps_rebuilt++;
      }
      if (options.keep_draco) {
        PrimitiveGeometry decoded;
        size_t bytes = 0;
        err = write_primitive_draco(model, prim, geom, options.draco, replaced, decoded, bytes);
        if (!err.empty()) return where + err;
      } else {
        reserve_plain_bytes(model, geom);
        write_primitive_plain(model, prim, geom, replaced);
      }
      report.primitives_decoded++;
    }
  }
  retire_extension_if_unused(model, kDracoExtension);
  retire_extension_if_unused(model, ext::kName);
  retire_mesh_quantization_if_unused(model);
  compact_buffers(model, replaced);
  return {};
}

}  // namespace gltfwarp
