// Cutting a primitive into parts that become primitives of their own: the
// way a primitive whose atlas would pass one page of --max-atlas-size gets
// several pages (codec/encode/atlas/pages.h), since a glTF texture slot names one image.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <tiny_gltf.h>

#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {

// The faces of one part, with the vertices they use (renumbered in order of
// first use) and every attribute of those vertices.
PrimitiveGeometry part_geometry(const PrimitiveGeometry& geom, std::span<const uint32_t> part_of_face,
                                uint32_t part);

// Rewrites primitive `primitive` of mesh `mesh` as plain accessors holding
// part 0 of `geom` (its geometry as read_primitive gives it; one part per
// face) and appends each later part to the same mesh: a copy of the
// primitive (material, mode, extensions, extras) with accessors of its own.
// Every vertex attribute is kept. The accessors it supersedes go to
// `replaced`. Returns the appended primitives' indices.
std::vector<int> cut_primitive(tinygltf::Model& model, int mesh, int primitive, const PrimitiveGeometry& geom,
                               std::span<const uint32_t> part_of_face, uint32_t part_count,
                               std::vector<int>& replaced);

}  // namespace gltfwarp
