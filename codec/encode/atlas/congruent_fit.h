// Texel reuse (twin_partition.h): where a copy patch's layout lands on its
// original's. The copy's replay is the original's up to a rotation, maybe a
// mirror, and the small differences of two nearly congruent meshes, so the
// best similarity (least squares over the corresponding corners) says where
// its fine placement (format 1.3) must put it, and the largest residual says
// whether the two are congruent enough to share texels.
#pragma once

#include <cstdint>
#include <span>

#include "format/bitstream/uvmap.h"

namespace gltfwarp {

// to ~ [a -b; b a] * M * from + (tx, ty), M = diag(1, -1) when mirror.
struct SimilarityFit {
  bool ok = false;  // at least two distinct points
  bool mirror = false;
  double a = 1, b = 0, tx = 0, ty = 0;
  double max_residual = 0;  // largest |to - fit(from)| over the pairs, in the points' units
};

// Point pairs: from_xy[2i], from_xy[2i + 1] -> to_xy[2i], to_xy[2i + 1].
// Tries both handednesses and keeps the one with the smaller largest residual.
SimilarityFit fit_similarity(std::span<const double> from_xy, std::span<const double> to_xy);

// The fine placement that puts a copy patch, related to its original's
// patch-local frame by `fit`, on the texels where `original` (a placement
// the packer made: not fine) placed it (texel_scale: the map's). The copy keeps the original's scale step and
// page; the result's x, y lie in [0, width] x [0, height].
PatchPlacement copy_placement(const PatchPlacement& original, const SimilarityFit& fit, double texel_scale,
                              uint32_t width, uint32_t height);

}  // namespace gltfwarp
