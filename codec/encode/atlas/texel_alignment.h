// Texel-exact patches: where a patch's source map is one similarity (a flat
// face of a box, a plane, a trim: the source image laid on the surface
// without stretch), the atlas can hold the source's own texels instead of a
// resampling of them. The patch is placed (fine placement, format 1.3) at
// exactly the source's density, turned by a multiple of 90 degrees against
// the source image, with its texel centres on the source's: the warp then
// reads every texel at a source texel centre, where its interpolating
// filter returns that texel, and a viewer's bilinear filter shows what it
// showed on the source. Resampling cost is what the warp's quality loss is
// made of (issue 16), so these patches cost nothing in quality.
#pragma once

#include <cstdint>
#include <span>

#include "codec/encode/atlas/congruent_fit.h"

namespace gltfwarp {

// The similarity from a patch's layout to its source texels, when one
// exists: source texel = [a -b; b a] * M * p + (tx, ty), M = diag(1, -1)
// when mirror, with every corner within `max_residual` source texels.
// ok = false otherwise (stretch, a source seam inside the patch, a
// degenerate patch). Source texels: u * image_width, v * image_height.
SimilarityFit fit_texel_alignment(std::span<const double> corner_xy, std::span<const float> source_uv,
                                  std::span<const uint32_t> faces, uint32_t image_width,
                                  uint32_t image_height, double max_residual);

// The fine placement's rotation, scale and fractional origin that land the
// patch on the source's texel grid after `turn` quarter turns (0..3) of the
// source image, at a base scale of `scale` atlas texels per model unit (the
// map's texel_scale): `scale_step` keeps (cos_q, sin_q) near kFineUnit, and
// (frac_x, frac_y) in [0, 1], in 1/256 texel steps, is the origin's part that
// whole texels cannot give. Where a coarse placement (a rotation code, a
// scale step, whole texels, no mirror) lands every corner of the patch,
// which reaches `extent` model units from its origin, within 1/100 texel of
// the same place, `coarse` is set with its `rotation`: fewer bytes in the
// stream, and the placement a plane laid out at its source's density
// already had. False when the source density lies outside the format's
// scale range.
struct AlignedTransform {
  int32_t scale_step = 0;
  int32_t cos_q = 0, sin_q = 0;  // never mirrored (a reflection is a turn of the lattice)
  double frac_x = 0, frac_y = 0;
  bool coarse = false;
  uint32_t rotation = 0;
};
bool aligned_transform(const SimilarityFit& fit, int turn, double scale, double extent,
                       AlignedTransform& out);

// MIP blocks. A viewer minifies through a pyramid of 2x2 box filters: texel
// j of level k averages texels [2^k j, 2^k (j + 1)) of level 0. An aligned
// patch's texels are the source's, but its level-k texels are the source's
// only where both grids of 2^k-blocks line up; shifted by one texel, 1-texel
// detail (text, lines) blurs differently at every level a minified view
// samples (VertexColorTest: 24 dB at level 1). The whole-texel position x
// of a patch lines them up when x = residue (mod block), per atlas axis.
// sc, ss, ox, oy: the patch's mask frame, atlas = (sc, -ss; ss, sc) p +
// (ox, oy) + whole position, as build_mask takes it. block: a power of 2.
struct BlockResidue {
  int x = 0, y = 0;
};
BlockResidue mip_block_residue(const SimilarityFit& fit, double sc, double ss, double ox, double oy,
                               int block);

}  // namespace gltfwarp
