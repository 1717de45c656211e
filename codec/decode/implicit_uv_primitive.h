// The glTF side of one implicit-UV primitive: reading our extension object
// and turning decoded geometry + bitstream into a primitive with TEXCOORD_0.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include <tiny_gltf.h>

#include "format/gltf/extension.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {

// What the UV replay reads from one implicit-UV primitive, checked so that
// neither the bitstream reader nor the replay can read out of bounds.
struct ReplayInput {
  std::span<const uint8_t> bitstream;         // the extension's bufferView, inside its buffer
  const VertexAttribute* position = nullptr;  // 3 components, every one finite
};

// Fills `in` from the primitive's extension object and its decoded geometry
// `geom` (which `in.position` then points into). Empty string or a one-line
// error. Every reader of our streams (decode, info) goes through it.
std::string replay_input(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                         const PrimitiveGeometry& geom, ReplayInput& in);

// Rebuilds TEXCOORD_0 for `geom` (the primitive's decoded geometry): runs
// decode_uvs on the embedding mesh, splits every point whose corners got
// different UVs, and, when the extension asks for it, adds MikkTSpace-style
// TANGENTs from the new UVs. Empty string or a one-line error.
std::string rebuild_texcoords(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                              PrimitiveGeometry& geom);

// Splits points by per-corner UV: one output vertex per distinct (point, uv)
// pair, in order of first use; every attribute is carried along and
// TEXCOORD_0 is set. `corner_uv` holds 2 floats per corner of `geom`.
void split_by_corner_uv(PrimitiveGeometry& geom, const std::vector<float>& corner_uv);

}  // namespace gltfwarp
