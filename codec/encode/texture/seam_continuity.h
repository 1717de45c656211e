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

// What the encoder lets a patch cross where a seam has one chart on both
// sides (a slit, source_charts.h): a step of up to 32 levels (of 255) on
// average. Cutting a slit splits its chart, which costs seams and gutters
// where the split runs; an atlas texel's smear of a slight step costs less.
// MultiUVTest's cube net (steps of 38 to 65 levels) gained 4.3 dB surface
// PSNR in 1.2% fewer bytes when cut. Cut at 16 levels, the
// CesiumMilkTruck's atlas grew 3.6% at the same surface PSNR (fixed
// density) and the Duck's file 1.8% for -0.5 dB in 256-px views.
inline constexpr SeamContinuityOptions kSlitCrossable{5, 32.0, 256.0};

// A SeamTest that samples every texture in `textures` (a material's
// TEXCOORD_0 slots, as a viewer samples them) on both sides of the edge; the
// seam is hidden only if it is in all of them. The samplers must outlive
// the test.
SeamTest texture_seam_test(std::span<const TextureSampler> textures,
                           const SeamContinuityOptions& options = {});

}  // namespace gltfwarp
