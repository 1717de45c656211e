// Tangent frames for tangent-space normal maps, in the MikkTSpace convention
// that glTF viewers use (glTF 2.0 spec, "Meshes": bitangent =
// cross(normal, tangent.xyz) * tangent.w).
//
// Source: Mikkelsen, "Simulation of Wrinkled Surfaces Revisited" (MSc thesis,
// 2008) and its reference implementation mikktspace.c, reproduced here without
// the library (Debian does not package it). Per face, the tangent is the
// direction of increasing u and the bitangent that of decreasing v (glTF's v
// runs down the image; this equals mikktspace.c on the raw UVs with the sign
// negated, as three.js does for glTF). At each corner the face tangent is
// projected onto the corner normal's plane, normalized and weighted by the
// corner angle, then summed over the corners that share position, normal, UV
// and orientation (MikkTSpace's welding and its split of mirrored faces).
//
// Deviations from mikktspace.c: (1) no splitting of a vertex group into
// sub-groups of faces whose tangents diverge by more than its angular
// threshold, (2) degenerate faces contribute nothing instead of borrowing a
// neighbour's frame, (3) double precision. On smooth, non-degenerate UV maps
// the results agree to a few 1e-3 in direction.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"

namespace gltfwarp {

// Per-corner tangents, 4 floats per corner (xyz unit, w = +1 or -1), from the
// mesh positions, per-corner normals (3 per corner) and per-corner UVs
// (2 per corner). Corners whose frame is undefined (no UV area) get a unit
// vector orthogonal to the normal and w = 1.
std::vector<float> corner_tangents(const TriMesh& mesh, std::span<const float> corner_normals,
                                   std::span<const float> corner_uv);

// The TANGENT attribute of an indexed glTF primitive: 4 floats per vertex,
// from positions (3 per vertex), normals (3 per vertex), TEXCOORD_0 (2 per
// vertex) and triangle indices.
std::vector<float> vertex_tangents(std::span<const float> positions, std::span<const float> normals,
                                   std::span<const float> uvs, std::span<const uint32_t> indices);

// Flat per-corner normals (the face normal at its three corners), which glTF
// viewers use when a primitive has no NORMAL.
std::vector<float> flat_corner_normals(const TriMesh& mesh);

// Per-corner view of a per-vertex attribute (n floats per vertex).
std::vector<float> per_corner(const TriMesh& mesh, std::span<const float> per_vertex, int n);

}  // namespace gltfwarp
