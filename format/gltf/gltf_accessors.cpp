#include "format/gltf/gltf_accessors.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace gltfwarp {

size_t component_size(int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

int accessor_type_for(int components) {
  switch (components) {
    case 1:
      return TINYGLTF_TYPE_SCALAR;
    case 2:
      return TINYGLTF_TYPE_VEC2;
    case 3:
      return TINYGLTF_TYPE_VEC3;
    case 4:
      return TINYGLTF_TYPE_VEC4;
    case 9:
      return TINYGLTF_TYPE_MAT3;
    case 16:
      return TINYGLTF_TYPE_MAT4;
    default:
      return TINYGLTF_TYPE_SCALAR;
  }
}

size_t VertexAttribute::element_size() const {
  return component_size(component_type) * static_cast<size_t>(components);
}

float VertexAttribute::get(size_t e, int i) const {
  const size_t cs = component_size(component_type);
  const uint8_t* p = data.data() + (e * static_cast<size_t>(components) + static_cast<size_t>(i)) * cs;
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? p[0] / 255.0f : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<int8_t>(p[0]);
      return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return static_cast<float>(v);
    }
    case TINYGLTF_COMPONENT_TYPE_INT: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return static_cast<float>(v);
    }
    default:
      return 0.0f;
  }
}

int value_index(const tinygltf::Value& v) {
  if (v.IsInt()) {
    const int i = v.Get<int>();
    return i >= 0 ? i : -1;
  }
  if (v.IsReal()) {
    const double d = v.Get<double>();
    if (d >= 0 && d <= static_cast<double>(std::numeric_limits<int>::max()) && d == std::floor(d))
      return static_cast<int>(d);
  }
  return -1;
}

std::string extension_view_bytes(const tinygltf::Model& model, const tinygltf::Value& ext,
                                 const std::string& extension, std::span<const uint8_t>& bytes) {
  const int view = value_index(ext.Get("bufferView"));
  if (view < 0 || static_cast<size_t>(view) >= model.bufferViews.size())
    return extension + " names a missing bufferView";
  const auto& bv = model.bufferViews[view];
  if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model.buffers.size() ||
      bv.byteOffset > model.buffers[bv.buffer].data.size() ||
      bv.byteLength > model.buffers[bv.buffer].data.size() - bv.byteOffset)
    return extension + " bufferView runs past its buffer";
  bytes = {model.buffers[bv.buffer].data.data() + bv.byteOffset, bv.byteLength};
  return {};
}

std::vector<float> VertexAttribute::to_floats() const {
  std::vector<float> out(count() * static_cast<size_t>(components));
  for (size_t e = 0; e < count(); ++e)
    for (int i = 0; i < components; ++i) out[e * components + i] = get(e, i);
  return out;
}

VertexAttribute VertexAttribute::from_floats(const std::string& semantic, int components,
                                             const std::vector<float>& values) {
  VertexAttribute a;
  a.semantic = semantic;
  a.component_type = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.components = components;
  a.data.resize(values.size() * 4);
  std::memcpy(a.data.data(), values.data(), a.data.size());
  return a;
}

namespace {

// Checks that `count` elements of `elem` bytes, `stride` apart, starting
// `byte_offset` into bufferView `view_index`, lie inside the view and the
// view inside its buffer. Allocates nothing.
std::string check_view_range(const tinygltf::Model& model, int view_index, size_t byte_offset, size_t count,
                             size_t elem, size_t& stride) {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
    return "bufferView " + std::to_string(view_index) + " does not exist";
  const auto& view = model.bufferViews[view_index];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    return "bufferView " + std::to_string(view_index) + " names a missing buffer";
  const auto& buf = model.buffers[view.buffer].data;
  stride = view.byteStride ? view.byteStride : elem;
  if (stride < elem)
    return "bufferView " + std::to_string(view_index) + " has a byteStride below the element size";
  if (view.byteOffset > buf.size() || view.byteLength > buf.size() - view.byteOffset)
    return "bufferView " + std::to_string(view_index) + " runs past the end of its buffer";
  if (count == 0) return {};
  // count <= kMaxAccessorElements and stride < 2^32: no overflow in 64 bits.
  if (count > kMaxAccessorElements || stride > std::numeric_limits<uint32_t>::max())
    return "accessor on bufferView " + std::to_string(view_index) + " is too large";
  if (byte_offset > view.byteLength || (count - 1) * stride + elem > view.byteLength - byte_offset)
    return "accessor runs past the end of bufferView " + std::to_string(view_index);
  return {};
}

// Copies elements checked by check_view_range into `out`.
void copy_strided(const tinygltf::Model& model, int view_index, size_t byte_offset, size_t count, size_t elem,
                  size_t stride, uint8_t* out) {
  if (!count) return;
  const auto& view = model.bufferViews[view_index];
  const uint8_t* base = model.buffers[view.buffer].data.data() + view.byteOffset + byte_offset;
  for (size_t i = 0; i < count; ++i) std::memcpy(out + i * elem, base + i * stride, elem);
}

size_t zero_fill_budget(const tinygltf::Model& model) {
  size_t bytes = 0;
  for (const auto& b : model.buffers) bytes += b.data.size();
  return std::max(kMinZeroFillBudget, bytes > (SIZE_MAX / 8) ? SIZE_MAX / 2 : 4 * bytes);
}

}  // namespace

std::string read_accessor(const tinygltf::Model& model, int index, VertexAttribute& out) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
    return "accessor " + std::to_string(index) + " does not exist";
  const auto& acc = model.accessors[index];
  const std::string name = "accessor " + std::to_string(index);
  out.component_type = acc.componentType;
  out.components = component_count(acc.type);
  out.normalized = acc.normalized;
  out.data.clear();
  const size_t elem = out.element_size();
  if (!elem) return name + " has an unknown type";
  if (acc.count > kMaxAccessorElements) return name + " declares too many elements";
  // Validate every source range before allocating anything.
  size_t stride = 0;
  if (acc.bufferView >= 0) {
    std::string err = check_view_range(model, acc.bufferView, acc.byteOffset, acc.count, elem, stride);
    if (!err.empty()) return name + ": " + err;
  } else if (acc.count * elem > zero_fill_budget(model)) {
    return name + " declares " + std::to_string(acc.count * elem) + " bytes with no data behind them";
  }
  size_t n = 0, ics = 0, istride = 0, vstride = 0;
  if (acc.sparse.isSparse) {
    const auto& sp = acc.sparse;
    if (sp.count < 0 || static_cast<size_t>(sp.count) > acc.count)
      return "sparse " + name + " has a count outside [0, " + std::to_string(acc.count) + "]";
    n = static_cast<size_t>(sp.count);
    ics = component_size(sp.indices.componentType);
    if (!ics || sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
        sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_INT)
      return "sparse " + name + " has a bad index type";
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0)
      return "sparse " + name + " has a negative byteOffset";
    std::string err = check_view_range(model, sp.indices.bufferView,
                                       static_cast<size_t>(sp.indices.byteOffset), n, ics, istride);
    if (err.empty())
      err = check_view_range(model, sp.values.bufferView, static_cast<size_t>(sp.values.byteOffset), n, elem,
                             vstride);
    if (!err.empty()) return "sparse " + name + ": " + err;
    // Sparse index and value views are tightly packed (glTF forbids a stride).
    istride = ics;
    vstride = elem;
  }

  out.data.assign(acc.count * elem, 0);
  if (acc.bufferView >= 0)
    copy_strided(model, acc.bufferView, acc.byteOffset, acc.count, elem, stride, out.data.data());
  if (n) {
    const auto& sp = acc.sparse;
    std::vector<uint8_t> idx(n * ics), vals(n * elem);
    copy_strided(model, sp.indices.bufferView, static_cast<size_t>(sp.indices.byteOffset), n, ics, istride,
                 idx.data());
    copy_strided(model, sp.values.bufferView, static_cast<size_t>(sp.values.byteOffset), n, elem, vstride,
                 vals.data());
    for (size_t i = 0; i < n; ++i) {
      uint32_t k = 0;
      if (ics == 1) k = idx[i];
      if (ics == 2) {
        uint16_t v;
        std::memcpy(&v, &idx[i * 2], 2);
        k = v;
      }
      if (ics == 4) std::memcpy(&k, &idx[i * 4], 4);
      if (k >= acc.count) {
        out.data.clear();
        return "sparse " + name + " has an index out of range";
      }
      std::memcpy(out.data.data() + size_t{k} * elem, vals.data() + i * elem, elem);
    }
  }
  return {};
}

std::string read_triangles(const tinygltf::Model& model, const tinygltf::Primitive& prim, size_t vertex_count,
                           std::vector<uint32_t>& tris) {
  std::vector<uint32_t> idx;
  if (prim.indices >= 0) {
    VertexAttribute a;
    std::string err = read_accessor(model, prim.indices, a);
    if (!err.empty()) return err;
    if (a.components != 1 || a.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT)
      return "indices accessor " + std::to_string(prim.indices) + " is not an unsigned integer scalar";
    idx.resize(a.count());
    for (size_t i = 0; i < idx.size(); ++i) {
      const size_t cs = component_size(a.component_type);
      uint32_t v = 0;
      if (cs == 1) v = a.data[i];
      if (cs == 2) {
        uint16_t s;
        std::memcpy(&s, &a.data[i * 2], 2);
        v = s;
      }
      if (cs == 4) std::memcpy(&v, &a.data[i * 4], 4);
      if (v >= vertex_count)
        return "index " + std::to_string(v) + " is out of range (" + std::to_string(vertex_count) +
               " vertices)";
      idx[i] = v;
    }
  } else {
    idx.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) idx[i] = static_cast<uint32_t>(i);
  }
  tris.clear();
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    tris.assign(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(idx.size() / 3 * 3));
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 2; i < idx.size(); ++i) {
      // Every other triangle flips so all keep the strip's winding.
      if (i % 2 == 0)
        tris.insert(tris.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else
        tris.insert(tris.end(), {idx[i - 1], idx[i - 2], idx[i]});
    }
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 2; i < idx.size(); ++i) tris.insert(tris.end(), {idx[0], idx[i - 1], idx[i]});
  } else {
    return "primitive mode " + std::to_string(mode) + " is not triangles";
  }
  return {};
}

int add_buffer_view(tinygltf::Model& model, const std::vector<uint8_t>& bytes, int target) {
  if (model.buffers.empty()) model.buffers.emplace_back();
  auto& buf = model.buffers[0].data;
  while (buf.size() % 4) buf.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = bytes.size();
  view.target = target;
  buf.insert(buf.end(), bytes.begin(), bytes.end());
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model& model, const VertexAttribute& attr, int target) {
  tinygltf::Accessor acc;
  acc.bufferView = add_buffer_view(model, attr.data, target);
  acc.componentType = attr.component_type;
  acc.normalized = attr.normalized;
  acc.type = accessor_type_for(attr.components);
  acc.count = attr.count();
  if (attr.semantic == "POSITION" && acc.count) {
    // As many components as the data has (a malformed file may declare
    // POSITION as anything).
    const int n = attr.components;
    acc.minValues.assign(n, std::numeric_limits<double>::infinity());
    acc.maxValues.assign(n, -std::numeric_limits<double>::infinity());
    if (attr.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT) {  // get() without the per-value switch
      const uint8_t* p = attr.data.data();
      for (size_t e = 0; e < acc.count; ++e)
        for (int i = 0; i < n; ++i, p += 4) {
          float v;
          std::memcpy(&v, p, 4);
          acc.minValues[i] = std::min<double>(acc.minValues[i], v);
          acc.maxValues[i] = std::max<double>(acc.maxValues[i], v);
        }
    } else {
      for (size_t e = 0; e < acc.count; ++e)
        for (int i = 0; i < n; ++i) {
          acc.minValues[i] = std::min<double>(acc.minValues[i], attr.get(e, i));
          acc.maxValues[i] = std::max<double>(acc.maxValues[i], attr.get(e, i));
        }
    }
  }
  model.accessors.push_back(acc);
  return static_cast<int>(model.accessors.size() - 1);
}

int add_index_accessor(tinygltf::Model& model, const std::vector<uint32_t>& indices, size_t vertex_count) {
  VertexAttribute a;
  a.components = 1;
  if (vertex_count <= 0xFFFF) {
    a.component_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    a.data.resize(indices.size() * 2);
    for (size_t i = 0; i < indices.size(); ++i) {
      const auto v = static_cast<uint16_t>(indices[i]);
      std::memcpy(&a.data[i * 2], &v, 2);
    }
  } else {
    a.component_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.data.resize(indices.size() * 4);
    std::memcpy(a.data.data(), indices.data(), indices.size() * 4);
  }
  return add_accessor(model, a, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
}

}  // namespace gltfwarp
