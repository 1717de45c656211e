// The mesh the layout replay runs on, built the same way by encoder and
// decoder from what Draco decodes: vertices are the decoded positions welded
// by exact bit equality (first appearance in point order), so charts run
// across hard-edge normal splits. No tolerance, no threshold: both sides
// compute the same welding from the same bits.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"
#include "format/gltf/gltf_accessors.h"

namespace gltfwarp {

// A triangle index past the points becomes this vertex, so that the replay
// and decode_uvs reject the mesh (bad_mesh) instead of reading vertex 0.
inline constexpr uint32_t kInvalidVertex = UINT32_MAX;

// `positions` must have 3 components. point_to_vertex receives, for each
// point, its vertex in the returned mesh. Faces keep their order.
TriMesh embedding_mesh(const VertexAttribute& positions, const std::vector<uint32_t>& triangles,
                       std::vector<uint32_t>& point_to_vertex);

// The same over plain floats, 3 per point.
TriMesh embedding_mesh(std::span<const float> xyz, std::span<const uint32_t> triangles,
                       std::vector<uint32_t>& point_to_vertex);

}  // namespace gltfwarp
