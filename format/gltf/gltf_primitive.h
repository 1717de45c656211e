// One glTF primitive's geometry as packed arrays: read from plain or
// Draco-compressed accessors, written back as plain accessors or as
// KHR_draco_mesh_compression.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "format/gltf/draco_geometry.h"
#include "format/gltf/gltf_accessors.h"

namespace gltfwarp {

inline constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";
inline constexpr const char* kMeshQuantization = "KHR_mesh_quantization";

struct PrimitiveGeometry {
  std::vector<VertexAttribute> attributes;  // semantic set, one count
  std::vector<uint32_t> triangles;          // three vertex ids per face
  size_t vertex_count() const { return attributes.empty() ? 0 : attributes[0].count(); }
  const VertexAttribute* find(const std::string& semantic) const;
  VertexAttribute* find(const std::string& semantic);
  void erase(const std::string& semantic);
};

// True for modes we turn into triangle lists (TRIANGLES, STRIP, FAN).
bool is_triangle_mode(int mode);

// Reads the primitive's attributes and triangles, decoding Draco if the
// primitive carries KHR_draco_mesh_compression. Empty string or a one-line
// error; every accessor and index is checked.
std::string read_primitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                           PrimitiveGeometry& out);

// Replaces the primitive's attributes and indices by new plain accessors
// (mode becomes TRIANGLES). Old accessor ids are appended to `replaced`.
void write_primitive_plain(tinygltf::Model& model, tinygltf::Primitive& prim, const PrimitiveGeometry& geom,
                           std::vector<int>& replaced);
// Bytes write_primitive_plain stores: every attribute, and the indices as
// uint16 when the vertices fit, else uint32.
size_t plain_geometry_bytes(const PrimitiveGeometry& geom);

// "" when every float attribute is finite, else a one-line error naming the
// attribute (Draco quantizes over each attribute's range: one NaN or infinity
// makes every value garbage, and its float-to-int casts undefined).
std::string non_finite_attribute(const PrimitiveGeometry& geom);

// Encodes with Draco and decodes the bytes again: `decoded` receives what
// every decoder will see. Float attributes holding NaN or infinities are
// refused. A pure function of its arguments (the encoder runs it for
// several primitives side by side).
std::string draco_round_trip(const PrimitiveGeometry& geom, const DracoOptions& options,
                             DracoEncoded& encoded, PrimitiveGeometry& decoded);

// Points the primitive at `encoded` (draco_round_trip) in a new bufferView;
// the accessors keep type and count but no bufferView, as the extension
// prescribes, and min/max from `decoded`. Old accessor ids go to `replaced`.
void attach_draco(tinygltf::Model& model, tinygltf::Primitive& prim, const DracoEncoded& encoded,
                  const PrimitiveGeometry& decoded, std::vector<int>& replaced);

// draco_round_trip, then attach_draco; `draco_bytes` receives the bytes' size.
std::string write_primitive_draco(tinygltf::Model& model, tinygltf::Primitive& prim,
                                  const PrimitiveGeometry& geom, const DracoOptions& options,
                                  std::vector<int>& replaced, PrimitiveGeometry& decoded,
                                  size_t& draco_bytes);

// Adds extension `name` to extensionsUsed (and extensionsRequired when asked), once.
void declare_extension(tinygltf::Model& model, const std::string& name, bool required);
// Removes `name` from extensionsUsed/Required when no primitive uses it any more.
void retire_extension_if_unused(tinygltf::Model& model, const std::string& name);

// Whether any mesh attribute (or morph target) has a component type that
// glTF 2.0 core does not allow, i.e. still needs KHR_mesh_quantization.
bool needs_mesh_quantization(const tinygltf::Model& model);
// Removes KHR_mesh_quantization from extensionsUsed/Required when nothing
// needs it any more (e.g. the only quantized attribute was TEXCOORD_0).
void retire_mesh_quantization_if_unused(tinygltf::Model& model);

}  // namespace gltfwarp
