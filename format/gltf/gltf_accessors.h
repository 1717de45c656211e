// Reading glTF accessors into tightly packed arrays, and writing packed
// arrays back as new accessors. Handles byteStride, sparse accessors,
// normalized integers and bad indices with an error, never a crash.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace gltfwarp {

// One vertex attribute, tightly packed in its glTF component type.
struct VertexAttribute {
  std::string semantic;    // "POSITION", "NORMAL", "TEXCOORD_1", "JOINTS_0", "_ID", ...
  int component_type = 0;  // glTF componentType (5120..5126)
  int components = 0;      // 1..4 for SCALAR..VEC4, 16 for MAT4
  bool normalized = false;
  std::vector<uint8_t> data;  // count * components * component_size bytes

  size_t element_size() const;
  size_t count() const { return element_size() ? data.size() / element_size() : 0; }
  // Component i of element e as a float (normalized ints mapped as glTF says).
  float get(size_t e, int i) const;
  // Every component as floats, `components` per element.
  std::vector<float> to_floats() const;
  // A FLOAT attribute holding `values` (`components` per element).
  static VertexAttribute from_floats(const std::string& semantic, int components,
                                     const std::vector<float>& values);
};

// Largest element count an accessor may declare (2^28: far beyond any real
// asset, and count * 64-byte elements stays in range).
inline constexpr size_t kMaxAccessorElements = size_t{1} << 28;
// Accessors without a bufferView are zero-filled; a file may declare at most
// max(this, 4 x its buffer bytes) of them, so a tiny file cannot demand
// gigabytes.
inline constexpr size_t kMinZeroFillBudget = size_t{64} << 20;

// A JSON number in an extension or extras that names an index: -1 unless it
// is an integer in [0, INT_MAX] (tinygltf's GetNumberAsInt casts any double,
// which is undefined behaviour past int's range).
int value_index(const tinygltf::Value& v);

// The whole bufferView that an extension object's "bufferView" names
// (Draco's, ours), checked to lie inside its buffer: into `bytes`. Empty
// string, or a one-line error that starts with `extension`. The caller has
// checked that the object has a "bufferView".
std::string extension_view_bytes(const tinygltf::Model& model, const tinygltf::Value& ext,
                                 const std::string& extension, std::span<const uint8_t>& bytes);

size_t component_size(int component_type);
int component_count(int accessor_type);  // TINYGLTF_TYPE_* -> 1..16
int accessor_type_for(int components);   // inverse of component_count

// Reads accessor `index` into `out` (semantic left empty). Empty string on
// success, else a one-line reason. Every declared size is checked against
// the bytes that back it before anything is allocated.
std::string read_accessor(const tinygltf::Model& model, int index, VertexAttribute& out);

// Reads a primitive's triangle list: indices as given (or 0..n-1 when absent),
// triangle strips and fans converted to lists. Every index is checked
// against vertex_count.
std::string read_triangles(const tinygltf::Model& model, const tinygltf::Primitive& prim, size_t vertex_count,
                           std::vector<uint32_t>& triangles);

// Appends raw bytes as a new bufferView of buffer 0 (4-byte aligned); returns its index.
int add_buffer_view(tinygltf::Model& model, const std::vector<uint8_t>& bytes, int target = 0);

// Appends `data` as a new bufferView (+ accessor) in buffer 0 and returns the
// accessor index. min/max are filled for POSITION as the spec requires.
int add_accessor(tinygltf::Model& model, const VertexAttribute& attr, int target /* 34962/34963 or 0 */);
int add_index_accessor(tinygltf::Model& model, const std::vector<uint32_t>& indices, size_t vertex_count);

}  // namespace gltfwarp
