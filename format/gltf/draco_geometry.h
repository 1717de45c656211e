// Geometry through Draco (KHR_draco_mesh_compression): packed glTF vertex
// attributes + a triangle list in, a Draco bitstream out, and back.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "format/gltf/gltf_accessors.h"

namespace gltfwarp {

// Quantization bits, with the defaults common glTF tools use so that
// comparisons against them are fair.
struct DracoOptions {
  int position_bits = 14;
  int normal_bits = 10;
  int color_bits = 8;
  int texcoord_bits = 12;
  int generic_bits = 12;
  int encoding_speed = 0;  // 0 = best compression (Draco's scale 0..10)
  int decoding_speed = 0;
};

struct DracoEncoded {
  std::vector<uint8_t> bytes;
  std::map<std::string, int> attribute_ids;  // glTF semantic -> Draco unique id
  std::string error;                         // empty when ok
};

// Encodes the attributes (all of one vertex count) and triangles.
DracoEncoded draco_encode(const std::vector<VertexAttribute>& attributes,
                          const std::vector<uint32_t>& triangles, const DracoOptions& options);

struct DracoDecoded {
  std::vector<VertexAttribute> attributes;  // in the order asked for
  std::vector<uint32_t> triangles;          // point indices, three per face
  size_t point_count = 0;
  std::string error;
};

// Decodes `bytes`; for each wanted attribute (semantic, Draco unique id,
// glTF component type, components, normalized) fills a packed array of
// that glTF type, as KHR_draco_mesh_compression prescribes.
struct DracoWanted {
  std::string semantic;
  int unique_id = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;
};
DracoDecoded draco_decode(const uint8_t* bytes, size_t size, const std::vector<DracoWanted>& wanted);

// `values` (`components` per element) as a Draco decoder returns them when
// the attribute they belong to, `attribute` (the same layout: all of its
// elements), was encoded quantized to `bits`: Draco's own range (the widest
// component's extent, from the smallest value of each) and rounding
// (AttributeQuantizationTransform). What an explicit-UV file's viewer
// samples: 12-bit UVs over a unit square move a 2048² texture's samples by
// up to a quarter texel. `values` as they are where Draco would not
// quantize (bits outside 1..30, or no attribute values).
std::vector<float> draco_quantized(std::span<const float> attribute, std::span<const float> values,
                                   int components, int bits);

// Welds vertices whose every attribute is byte-identical (after dropping
// UVs, vertices split only by UV seams become one). Rewrites `attributes`
// and `triangles`; returns for each new vertex one old vertex it came from.
std::vector<uint32_t> weld_vertices(std::vector<VertexAttribute>& attributes,
                                    std::vector<uint32_t>& triangles);

}  // namespace gltfwarp
