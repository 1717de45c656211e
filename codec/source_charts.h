// The source's own UV charts on the embedding mesh: faces joined across every
// edge whose two faces carry the same source UVs at both ends. A patch that
// crosses a source UV seam puts texels of two unrelated source regions side
// by side, and the viewer's bilinear filter blends them along the seam; the
// partition keeps each patch inside one chart instead (EmbedOptions::face_chart).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/mesh.h"

namespace gltfwarp {

// Chart id per face, numbered 0, 1, ... in order of each chart's lowest face.
// source_uv holds 2 floats per corner (6 per face); UVs compare bit for bit,
// as the source's shared vertices give equal floats and a seam does not.
// Requires valid indices (mesh_indices_valid).
std::vector<uint32_t> source_charts(const TriMesh& mesh, std::span<const float> source_uv);

}  // namespace gltfwarp
