// Atlas pages: how a texture set too large for one page of --max-atlas-size
// is spread over several instead of losing detail.
//
// A glTF texture slot names one image, so a primitive samples one page. An
// atlas group spreads its primitives over pages (assign_pages), and a
// primitive whose texels alone would pass a page is first cut into parts
// that each become a primitive of their own (codec/encode/cut_primitive.h writes
// them): along its source UV charts by the source's texel count, before it
// is partitioned (split_faces_into_parts), then along its patch boundaries
// by the layout's count (parts_of_patches), after any patch larger than a
// page was split (split_large_patches).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"

namespace gltfwarp {

// Share of a page's texels that the packer is counted on to cover: the
// corpus atlases fill 53-75% of their pages (gutters, patch outlines).
inline constexpr double kExpectedPageFill = 0.55;

// Texels a page of `max_size` squared can be expected to hold.
inline double page_capacity(uint32_t max_size) {
  return double(max_size) * double(max_size) * kExpectedPageFill;
}

// Groups items (by their texel counts) into pages of `capacity` texels,
// first-fit in index order. An item larger than a page gets a page of its
// own. Each page lists its items in increasing index, and pages are ordered
// by their first item. Non-finite or negative sizes count as 0.
std::vector<std::vector<size_t>> assign_pages(std::span<const double> texels, double capacity);

// Atlas texels of each patch as the packer scales it: each patch at its
// faces' median density (patch_densities, from layout_texel_density's
// face_density) times `factor`, or, with face_density empty, at `factor`
// texels per layout unit. Before the packer's rounding to scale steps.
std::vector<double> estimated_patch_texels(std::span<const double> corner_xy,
                                           std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                                           std::span<const double> face_density, double factor);

// split(capacity, count) with the capacity raised by a quarter at a time
// until it makes at most max_count parts: past the pages allowed, fewer,
// larger parts (their pages then shrink to fit). `count` receives the
// final number of parts. Stops once the capacity is no longer a positive
// finite number.
template <class Split>
auto within_part_count(double capacity, uint32_t max_count, Split split, uint32_t& count) {
  for (;; capacity *= 1.25) {
    auto parts = split(capacity, count);
    if (count <= max_count || !(capacity > 0) || !std::isfinite(capacity)) return parts;
  }
}

// Part (0, 1, ...) of each patch so that each part's texels stay within
// `capacity` where possible: patches in breadth-first order over shared
// vertices, each part filled before the next one opens, so every part is
// one region of neighbouring patches. A patch larger than a page is a part
// of its own. Cutting between patches adds no seam: their boundary is one
// already. Requires valid mesh indices and patch_of_face[f] < patch_count.
std::vector<uint32_t> parts_of_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                                       std::span<const double> patch_texels, double capacity,
                                       uint32_t& part_count);

// Part (0, 1, ...) of each face of a triangle list, before any partition
// exists: faces that share a vertex stay together (in a glTF mesh a UV seam
// splits its vertices, so these pieces are the source's UV charts: cutting
// between them adds no seam), with `halve_pieces` a piece larger than
// `capacity` is halved across the longest side of its box of face centroids
// until each half fits (else it is a part of its own), and the pieces go
// to parts with assign_pages. Requires valid mesh indices and one texel
// count per face.
std::vector<uint32_t> split_faces_into_parts(const TriMesh& mesh, std::span<const double> face_texels,
                                             double capacity, bool halve_pieces, uint32_t& part_count);

// A patch larger than a page cannot be cut between pages. Returns a chart
// per face (EmbedOptions::face_chart) that keeps `chart` (or, empty, one
// chart) and splits the faces of every patch whose texels pass `capacity`
// into connected regions of about half a page each, breadth-first over
// shared vertices from the region's lowest face: embedded again with it, no
// patch crosses a region. Empty when no patch passes a page. face_texels:
// one per face (estimated_face_texels).
std::vector<uint32_t> split_large_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                                          uint32_t patch_count, std::span<const double> face_texels,
                                          double capacity, std::span<const uint32_t> chart);

// Atlas texels of each face at its own density (face_density, from
// layout_texel_density) times `factor`, or at `factor` texels per layout
// unit when face_density is empty.
std::vector<double> estimated_face_texels(std::span<const double> corner_xy,
                                          std::span<const double> face_density, double factor);

}  // namespace gltfwarp
