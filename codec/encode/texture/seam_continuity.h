// Which source UV seams the texture hides: along a seam edge, the texels
// on the two sides agree. Artists often paint across their own seams (a
// body split in two charts, flat-coloured art); a patch may cross such a
// seam, since the viewer's filter blends two equal colours there. Where the
// two sides differ (a decal's edge, an atlas neighbour), it may not.
#pragma once

#include <span>

#include "codec/encode/partition/source_charts.h"
#include "codec/encode/texture/texture_sampler.h"

namespace gltfwarp {

struct SeamContinuityOptions {
  int samples = 5;         // points along the edge, at (i + 0.5) / samples
  double max_mean = 4.0;   // mean over the points of the largest channel difference (0..255) ...
  double max_peak = 16.0;  // ... and its largest value, both at most these
};

// A SeamTest that samples every texture in `textures` (a material's
// TEXCOORD_0 slots, as a viewer samples them) on both sides of the edge; the
// seam is hidden only if it is in all of them. The samplers must outlive
// the test.
SeamTest texture_seam_test(std::span<const TextureSampler> textures,
                           const SeamContinuityOptions& options = {});

}  // namespace gltfwarp
