// Draco bridge. Draco (Google, Apache-2.0) does the compression; this file
// only maps glTF's packed attributes onto draco::Mesh and back.
#include "format/gltf/draco_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <unordered_map>

#include <draco/attributes/attribute_quantization_transform.h>
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/core/quantization_utils.h>
#include <draco/mesh/mesh.h>

namespace gltfwarp {
namespace {

draco::DataType draco_type(int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return draco::DT_INT8;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return draco::DT_UINT8;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return draco::DT_INT16;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return draco::DT_UINT16;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return draco::DT_UINT32;
    case TINYGLTF_COMPONENT_TYPE_INT:
      return draco::DT_INT32;
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return draco::DT_FLOAT32;
    default:
      return draco::DT_INVALID;
  }
}

draco::GeometryAttribute::Type draco_semantic(const std::string& s) {
  if (s == "POSITION") return draco::GeometryAttribute::POSITION;
  if (s == "NORMAL") return draco::GeometryAttribute::NORMAL;
  if (s.rfind("COLOR_", 0) == 0) return draco::GeometryAttribute::COLOR;
  if (s.rfind("TEXCOORD_", 0) == 0) return draco::GeometryAttribute::TEX_COORD;
  return draco::GeometryAttribute::GENERIC;
}

// Draco codes an integer attribute's values (or their prediction residuals)
// as symbols and tabulates every symbol up to the largest one: values near
// 2^32 (an integer TEXCOORD_0 a fuzzer made, a 32-bit id) made it allocate
// 4 GB. Up to 2^24 the tables stay under 128 MB.
constexpr uint64_t kMaxDracoInteger = uint64_t{1} << 24;

// The largest magnitude among an integer attribute's stored values (0 for floats).
uint64_t largest_integer(const VertexAttribute& a) {
  const size_t cs = component_size(a.component_type);
  uint64_t most = 0;
  for (size_t i = 0; cs > 0 && i + cs <= a.data.size(); i += cs) {
    const uint8_t* p = a.data.data() + i;
    uint64_t v = 0;
    switch (a.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t u;
        std::memcpy(&u, p, 4);
        v = u;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_INT: {
        int32_t s;
        std::memcpy(&s, p, 4);
        v = uint64_t(std::abs(int64_t{s}));
        break;
      }
      default:
        return 0;  // floats, and 8- and 16-bit integers (at most 65535)
    }
    most = std::max(most, v);
  }
  return most;
}

template <typename T>
void convert_into(const draco::PointAttribute* att, draco::PointIndex p, int n, uint8_t* out) {
  T tmp[16] = {};
  att->ConvertValue<T>(att->mapped_index(p), static_cast<int8_t>(n), tmp);
  std::memcpy(out, tmp, sizeof(T) * static_cast<size_t>(n));
}

// Fast path of the conversion below when Draco holds exactly the glTF
// component type (the usual case: float positions and normals): plain copies,
// the same bytes ConvertValue would produce. Returns false to fall back.
bool copy_same_type(const draco::PointAttribute& att, const DracoWanted& w, int nc, size_t points,
                    uint8_t* out) {
  if (draco_type(w.component_type) != att.data_type() || att.buffer() == nullptr) return false;
  const size_t cs = component_size(w.component_type);
  const size_t src_elem = cs * static_cast<size_t>(att.num_components());
  const size_t dst_elem = cs * static_cast<size_t>(w.components);
  const size_t n = cs * static_cast<size_t>(nc);
  if (att.byte_stride() != static_cast<int64_t>(src_elem) || att.byte_offset() != 0) return false;
  const uint8_t* src = att.buffer()->data();
  const size_t values = att.size();
  if (att.buffer()->data_size() < values * src_elem) return false;
  for (size_t p = 0; p < points; ++p) {
    const uint32_t v = att.mapped_index(draco::PointIndex(static_cast<uint32_t>(p))).value();
    if (v >= values) return false;  // ConvertValue would read past the values; let it decide
    std::memcpy(out + p * dst_elem, src + size_t{v} * src_elem, n);
  }
  return true;
}

}  // namespace

DracoEncoded draco_encode(const std::vector<VertexAttribute>& attributes,
                          const std::vector<uint32_t>& triangles, const DracoOptions& o) {
  DracoEncoded r;
  if (attributes.empty()) {
    r.error = "no vertex attributes to encode";
    return r;
  }
  const size_t n = attributes[0].count();
  draco::Mesh mesh;
  mesh.set_num_points(static_cast<uint32_t>(n));
  const size_t faces = triangles.size() / 3;
  mesh.SetNumFaces(faces);
  for (size_t f = 0; f < faces; ++f) {
    draco::Mesh::Face face;
    for (int k = 0; k < 3; ++k) face[k] = draco::PointIndex(triangles[3 * f + k]);
    mesh.SetFace(draco::FaceIndex(static_cast<uint32_t>(f)), face);
  }
  for (const auto& a : attributes) {
    if (a.count() != n) {
      r.error = "attribute " + a.semantic + " has a different vertex count";
      return r;
    }
    const draco::DataType dt = draco_type(a.component_type);
    if (dt == draco::DT_INVALID || a.components < 1 || a.components > 4) {
      r.error = "attribute " + a.semantic + " has a type Draco cannot carry";
      return r;
    }
    if (const uint64_t most = largest_integer(a); most > kMaxDracoInteger) {
      r.error = "attribute " + a.semantic + " holds integers up to " + std::to_string(most) +
                ", past the 2^24 that Draco's integer coder tabulates";
      return r;
    }
    draco::GeometryAttribute ga;
    ga.Init(draco_semantic(a.semantic), nullptr, static_cast<uint8_t>(a.components), dt, a.normalized,
            static_cast<int64_t>(a.element_size()), 0);
    const int id = mesh.AddAttribute(ga, true, static_cast<uint32_t>(n));
    draco::PointAttribute* pa = mesh.attribute(id);
    for (size_t i = 0; i < n; ++i)
      pa->SetAttributeValue(draco::AttributeValueIndex(static_cast<uint32_t>(i)),
                            a.data.data() + i * a.element_size());
    r.attribute_ids[a.semantic] = static_cast<int>(pa->unique_id());
  }

  draco::Encoder enc;
  enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, o.position_bits);
  enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, o.normal_bits);
  enc.SetAttributeQuantization(draco::GeometryAttribute::COLOR, o.color_bits);
  enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, o.texcoord_bits);
  enc.SetAttributeQuantization(draco::GeometryAttribute::GENERIC, o.generic_bits);
  enc.SetSpeedOptions(o.encoding_speed, o.decoding_speed);
  draco::EncoderBuffer buf;
  const draco::Status st = enc.EncodeMeshToBuffer(mesh, &buf);
  if (!st.ok()) {
    r.error = std::string("Draco encoding failed: ") + st.error_msg();
    return r;
  }
  r.bytes.assign(buf.data(), buf.data() + buf.size());
  return r;
}

std::vector<float> draco_quantized(std::span<const float> attribute, std::span<const float> values,
                                   int components, int bits) {
  std::vector<float> out(values.begin(), values.end());
  if (components < 1 || components > 4 || bits < 1 || bits > 30) return out;
  const size_t n = attribute.size() / size_t(components);
  if (n == 0) return out;
  // Draco's parameters from the attribute, as its encoder computes them.
  draco::PointAttribute att;
  att.Init(draco::GeometryAttribute::GENERIC, int8_t(components), draco::DT_FLOAT32, false, n);
  for (size_t i = 0; i < n; ++i)
    att.SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &attribute[i * size_t(components)]);
  draco::AttributeQuantizationTransform transform;
  if (!transform.ComputeParameters(att, bits)) return out;
  // Then each value through the encoder's quantizer and the decoder's
  // dequantizer (GeneratePortableAttribute, InverseTransformAttribute).
  const int32_t max_quantized = int32_t((1u << uint32_t(bits)) - 1);
  draco::Quantizer quantizer;
  quantizer.Init(transform.range(), max_quantized);
  draco::Dequantizer dequantizer;
  if (!dequantizer.Init(transform.range(), max_quantized)) return out;
  // The quantizer's scale, in its own float arithmetic: a range of a few
  // denormals makes it infinite, and a value far outside the range a
  // quantized value past int; Draco's cast is undefined there, so such
  // values stay as they are (its own encoder meets the same input).
  const float inverse_delta = float(max_quantized) / transform.range();
  if (!std::isfinite(inverse_delta)) return out;
  for (size_t i = 0; i < out.size(); ++i) {
    const float min = transform.min_value(int(i % size_t(components)));
    if (!(std::abs((values[i] - min) * inverse_delta) < 2e9f)) continue;
    out[i] = dequantizer.DequantizeFloat(quantizer.QuantizeFloat(values[i] - min)) + min;
  }
  return out;
}

DracoDecoded draco_decode(const uint8_t* bytes, size_t size, const std::vector<DracoWanted>& wanted) {
  DracoDecoded r;
  draco::DecoderBuffer buf;
  buf.Init(reinterpret_cast<const char*>(bytes), size);
  draco::Decoder dec;
  auto status_or = dec.DecodeMeshFromBuffer(&buf);
  if (!status_or.ok()) {
    r.error = std::string("bad Draco data: ") + status_or.status().error_msg();
    return r;
  }
  std::unique_ptr<draco::Mesh> mesh = std::move(status_or).value();
  r.point_count = mesh->num_points();
  r.triangles.resize(static_cast<size_t>(mesh->num_faces()) * 3);
  for (uint32_t f = 0; f < mesh->num_faces(); ++f) {
    const auto& face = mesh->face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) {
      if (face[k].value() >= r.point_count) {
        r.error = "bad Draco data: face index out of range";
        return r;
      }
      r.triangles[3 * f + k] = face[k].value();
    }
  }
  for (const auto& w : wanted) {
    const draco::PointAttribute* att = mesh->GetAttributeByUniqueId(static_cast<uint32_t>(w.unique_id));
    if (!att) {
      r.error = "Draco data has no attribute " + std::to_string(w.unique_id) + " for " + w.semantic;
      return r;
    }
    VertexAttribute a;
    a.semantic = w.semantic;
    a.component_type = w.component_type;
    a.components = w.components;
    a.normalized = w.normalized;
    if (!a.element_size() || w.components < 1 || w.components > 16 || att->num_components() < 1) {
      r.error = "attribute " + w.semantic + " has a type Draco cannot carry";
      return r;
    }
    a.data.assign(r.point_count * a.element_size(), 0);
    const int nc = std::min<int>(w.components, att->num_components());
    if (copy_same_type(*att, w, nc, r.point_count, a.data.data())) {
      r.attributes.push_back(std::move(a));
      continue;
    }
    for (uint32_t p = 0; p < r.point_count; ++p) {
      uint8_t* out = a.data.data() + p * a.element_size();
      const draco::PointIndex pi(p);
      switch (w.component_type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          convert_into<float>(att, pi, nc, out);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          convert_into<uint8_t>(att, pi, nc, out);
          break;
        case TINYGLTF_COMPONENT_TYPE_BYTE:
          convert_into<int8_t>(att, pi, nc, out);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
          convert_into<uint16_t>(att, pi, nc, out);
          break;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
          convert_into<int16_t>(att, pi, nc, out);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          convert_into<uint32_t>(att, pi, nc, out);
          break;
        case TINYGLTF_COMPONENT_TYPE_INT:
          convert_into<int32_t>(att, pi, nc, out);
          break;
        default:
          break;
      }
    }
    r.attributes.push_back(std::move(a));
  }
  return r;
}

std::vector<uint32_t> weld_vertices(std::vector<VertexAttribute>& attributes,
                                    std::vector<uint32_t>& triangles) {
  const size_t n = attributes.empty() ? 0 : attributes[0].count();
  size_t row = 0;
  for (const auto& a : attributes) row += a.element_size();
  std::vector<uint8_t> key(row);
  std::unordered_map<std::string, uint32_t> seen;
  seen.reserve(n);
  std::vector<uint32_t> remap(n), origin;
  for (size_t v = 0; v < n; ++v) {
    size_t off = 0;
    for (const auto& a : attributes) {
      std::memcpy(key.data() + off, a.data.data() + v * a.element_size(), a.element_size());
      off += a.element_size();
    }
    auto [it, inserted] =
        seen.emplace(std::string(key.begin(), key.end()), static_cast<uint32_t>(origin.size()));
    if (inserted) origin.push_back(static_cast<uint32_t>(v));
    remap[v] = it->second;
  }
  for (auto& a : attributes) {
    std::vector<uint8_t> packed(origin.size() * a.element_size());
    for (size_t i = 0; i < origin.size(); ++i)
      std::memcpy(packed.data() + i * a.element_size(), a.data.data() + origin[i] * a.element_size(),
                  a.element_size());
    a.data.swap(packed);
  }
  for (auto& t : triangles) t = remap[t];
  return origin;
}

}  // namespace gltfwarp
