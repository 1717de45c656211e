#include "format/gltf/gltf_primitive.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gltfwarp {

const VertexAttribute* PrimitiveGeometry::find(const std::string& s) const {
  for (const auto& a : attributes)
    if (a.semantic == s) return &a;
  return nullptr;
}
VertexAttribute* PrimitiveGeometry::find(const std::string& s) {
  for (auto& a : attributes)
    if (a.semantic == s) return &a;
  return nullptr;
}
void PrimitiveGeometry::erase(const std::string& s) {
  attributes.erase(std::remove_if(attributes.begin(), attributes.end(),
                                  [&](const VertexAttribute& a) { return a.semantic == s; }),
                   attributes.end());
}

bool is_triangle_mode(int mode) {
  return mode < 0 || mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
         mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

namespace {

std::string read_draco_primitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                 const tinygltf::Value& ext, PrimitiveGeometry& out) {
  if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Has("attributes") ||
      !ext.Get("attributes").IsObject())
    return std::string(kDracoExtension) + " object is malformed";
  std::span<const uint8_t> view;
  if (std::string e = extension_view_bytes(model, ext, kDracoExtension, view); !e.empty()) return e;
  std::vector<DracoWanted> wanted;
  const auto& attrs = ext.Get("attributes");
  for (const auto& [semantic, acc_index] : prim.attributes) {
    if (acc_index < 0 || static_cast<size_t>(acc_index) >= model.accessors.size())
      return "attribute " + semantic + " names a missing accessor";
    if (!attrs.Has(semantic)) continue;  // stored uncompressed beside Draco
    const auto& acc = model.accessors[acc_index];
    DracoWanted w;
    w.semantic = semantic;
    w.unique_id = value_index(attrs.Get(semantic));
    if (w.unique_id < 0) return std::string(kDracoExtension) + " gives attribute " + semantic + " a bad id";
    w.component_type = acc.componentType;
    w.components = component_count(acc.type);
    w.normalized = acc.normalized;
    wanted.push_back(w);
  }
  DracoDecoded d = draco_decode(view.data(), view.size(), wanted);
  if (!d.error.empty()) return d.error;
  out.attributes = std::move(d.attributes);
  out.triangles = std::move(d.triangles);
  if (!out.find("POSITION")) return "primitive has no POSITION";
  // Attributes stored uncompressed beside the Draco data.
  for (const auto& [semantic, acc_index] : prim.attributes) {
    if (attrs.Has(semantic)) continue;
    const auto& acc = model.accessors[acc_index];
    if (acc.bufferView < 0 && !acc.sparse.isSparse) continue;  // declared only (e.g. our TEXCOORD_0)
    VertexAttribute a;
    std::string err = read_accessor(model, acc_index, a);
    if (!err.empty()) return err;
    a.semantic = semantic;
    if (a.count() != d.point_count) return "attribute " + semantic + " does not match the Draco point count";
    out.attributes.push_back(std::move(a));
  }
  return {};
}

void fill_min_max(tinygltf::Accessor& acc, const VertexAttribute& a) {
  acc.minValues.clear();
  acc.maxValues.clear();
  if (a.semantic != "POSITION" || !a.count()) return;
  const int n = a.components;  // 3 in any valid file
  acc.minValues.assign(n, std::numeric_limits<double>::infinity());
  acc.maxValues.assign(n, -std::numeric_limits<double>::infinity());
  for (size_t e = 0; e < a.count(); ++e)
    for (int i = 0; i < n; ++i) {
      acc.minValues[i] = std::min<double>(acc.minValues[i], a.get(e, i));
      acc.maxValues[i] = std::max<double>(acc.maxValues[i], a.get(e, i));
    }
}

}  // namespace

std::string read_primitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                           PrimitiveGeometry& out) {
  out = {};
  auto ext = prim.extensions.find(kDracoExtension);
  if (ext != prim.extensions.end()) return read_draco_primitive(model, prim, ext->second, out);
  size_t count = 0;
  bool first = true;
  for (const auto& [semantic, acc_index] : prim.attributes) {
    VertexAttribute a;
    std::string err = read_accessor(model, acc_index, a);
    if (!err.empty()) return "attribute " + semantic + ": " + err;
    a.semantic = semantic;
    if (!first && a.count() != count)
      return "attribute " + semantic + " has a different count from the others";
    count = a.count();
    first = false;
    out.attributes.push_back(std::move(a));
  }
  if (!out.find("POSITION")) return "primitive has no POSITION";
  return read_triangles(model, prim, count, out.triangles);
}

void write_primitive_plain(tinygltf::Model& model, tinygltf::Primitive& prim, const PrimitiveGeometry& geom,
                           std::vector<int>& replaced) {
  for (const auto& [s, idx] : prim.attributes) replaced.push_back(idx);
  if (prim.indices >= 0) replaced.push_back(prim.indices);
  prim.attributes.clear();
  for (const auto& a : geom.attributes)
    prim.attributes[a.semantic] = add_accessor(model, a, TINYGLTF_TARGET_ARRAY_BUFFER);
  prim.indices = add_index_accessor(model, geom.triangles, geom.vertex_count());
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.extensions.erase(kDracoExtension);
}

size_t plain_geometry_bytes(const PrimitiveGeometry& geom) {
  size_t bytes = geom.triangles.size() * (geom.vertex_count() <= 0xFFFF ? 2 : 4);
  for (const auto& a : geom.attributes) bytes += a.data.size();
  return bytes;
}

std::string non_finite_attribute(const PrimitiveGeometry& geom) {
  for (const auto& a : geom.attributes) {
    if (a.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) continue;
    for (size_t e = 0; e < a.count(); ++e)
      for (int i = 0; i < a.components; ++i)
        if (!std::isfinite(a.get(e, i))) return "attribute " + a.semantic + " holds a NaN or infinite value";
  }
  return "";
}

std::string draco_round_trip(const PrimitiveGeometry& geom, const DracoOptions& options,
                             DracoEncoded& encoded, PrimitiveGeometry& decoded) {
  if (std::string err = non_finite_attribute(geom); !err.empty()) return err;
  encoded = draco_encode(geom.attributes, geom.triangles, options);
  if (!encoded.error.empty()) return encoded.error;
  // Decode our own bytes: the decoder's mesh (order, quantized values) is the
  // only geometry the rest of the encoder may look at.
  std::vector<DracoWanted> wanted;
  for (const auto& a : geom.attributes)
    wanted.push_back(
        {a.semantic, encoded.attribute_ids.at(a.semantic), a.component_type, a.components, a.normalized});
  DracoDecoded dec = draco_decode(encoded.bytes.data(), encoded.bytes.size(), wanted);
  if (!dec.error.empty()) return "Draco round trip failed: " + dec.error;
  decoded.attributes = std::move(dec.attributes);
  decoded.triangles = std::move(dec.triangles);
  return {};
}

void attach_draco(tinygltf::Model& model, tinygltf::Primitive& prim, const DracoEncoded& encoded,
                  const PrimitiveGeometry& decoded, std::vector<int>& replaced) {
  for (const auto& [s, idx] : prim.attributes) replaced.push_back(idx);
  if (prim.indices >= 0) replaced.push_back(prim.indices);
  prim.attributes.clear();
  tinygltf::Value::Object attr_ids;
  for (const auto& a : decoded.attributes) {
    tinygltf::Accessor acc;
    acc.componentType = a.component_type;
    acc.normalized = a.normalized;
    acc.type = accessor_type_for(a.components);
    acc.count = a.count();
    fill_min_max(acc, a);
    model.accessors.push_back(acc);
    prim.attributes[a.semantic] = static_cast<int>(model.accessors.size() - 1);
    attr_ids[a.semantic] = tinygltf::Value(encoded.attribute_ids.at(a.semantic));
  }
  tinygltf::Accessor ind;
  ind.componentType = decoded.vertex_count() <= 0xFFFF ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                       : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  ind.type = TINYGLTF_TYPE_SCALAR;
  ind.count = decoded.triangles.size();
  model.accessors.push_back(ind);
  prim.indices = static_cast<int>(model.accessors.size() - 1);
  prim.mode = TINYGLTF_MODE_TRIANGLES;

  tinygltf::Value::Object ext;
  ext["bufferView"] = tinygltf::Value(add_buffer_view(model, encoded.bytes));
  ext["attributes"] = tinygltf::Value(attr_ids);
  prim.extensions[kDracoExtension] = tinygltf::Value(ext);
  declare_extension(model, kDracoExtension, true);
}

std::string write_primitive_draco(tinygltf::Model& model, tinygltf::Primitive& prim,
                                  const PrimitiveGeometry& geom, const DracoOptions& options,
                                  std::vector<int>& replaced, PrimitiveGeometry& decoded,
                                  size_t& draco_bytes) {
  DracoEncoded encoded;
  if (std::string err = draco_round_trip(geom, options, encoded, decoded); !err.empty()) return err;
  draco_bytes = encoded.bytes.size();
  attach_draco(model, prim, encoded, decoded, replaced);
  return {};
}

void declare_extension(tinygltf::Model& model, const std::string& name, bool required) {
  auto add = [&](std::vector<std::string>& list) {
    if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
  };
  add(model.extensionsUsed);
  if (required) add(model.extensionsRequired);
}

void retire_extension_if_unused(tinygltf::Model& model, const std::string& name) {
  for (const auto& mesh : model.meshes)
    for (const auto& prim : mesh.primitives)
      if (prim.extensions.count(name)) return;
  auto drop = [&](std::vector<std::string>& list) {
    list.erase(std::remove(list.begin(), list.end(), name), list.end());
  };
  drop(model.extensionsUsed);
  drop(model.extensionsRequired);
}

namespace {

// Whether glTF 2.0 core allows this attribute's component type; anything
// else needs KHR_mesh_quantization.
bool core_attribute_type(const std::string& semantic, const tinygltf::Accessor& acc, bool morph_target) {
  const int ct = acc.componentType;
  const bool f = ct == TINYGLTF_COMPONENT_TYPE_FLOAT;
  if (morph_target) return f;
  const bool unorm8 = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && acc.normalized;
  const bool unorm16 = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && acc.normalized;
  auto is = [&](const char* prefix) { return semantic.rfind(prefix, 0) == 0; };
  if (semantic == "POSITION" || semantic == "NORMAL" || semantic == "TANGENT") return f;
  if (is("TEXCOORD_") || is("COLOR_") || is("WEIGHTS_")) return f || unorm8 || unorm16;
  if (is("JOINTS_"))
    return !acc.normalized &&
           (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  return true;  // application-specific attributes (_FOO) are unconstrained
}

}  // namespace

bool needs_mesh_quantization(const tinygltf::Model& model) {
  auto check = [&](const std::string& semantic, int idx, bool target) {
    return idx >= 0 && static_cast<size_t>(idx) < model.accessors.size() &&
           !core_attribute_type(semantic, model.accessors[idx], target);
  };
  for (const auto& mesh : model.meshes)
    for (const auto& prim : mesh.primitives) {
      for (const auto& [s, idx] : prim.attributes)
        if (check(s, idx, false)) return true;
      for (const auto& target : prim.targets)
        for (const auto& [s, idx] : target)
          if (check(s, idx, true)) return true;
    }
  return false;
}

void retire_mesh_quantization_if_unused(tinygltf::Model& model) {
  if (needs_mesh_quantization(model)) return;
  auto drop = [&](std::vector<std::string>& list) {
    list.erase(std::remove(list.begin(), list.end(), std::string(kMeshQuantization)), list.end());
  };
  drop(model.extensionsUsed);
  drop(model.extensionsRequired);
}

}  // namespace gltfwarp
