// Surface quality at the MIP levels a viewer samples when it minifies, and
// in the worst region beside the mean, so that a localised crack or a
// gutter that runs out at a coarser level cannot hide in one full-resolution
// average.
//
// Level L is a screen footprint of 2^L texels of the coarser of the two
// grids on each face. A viewer reads each texture's MIP chain (box-filtered
// 2x2, as glGenerateMipmap builds a power-of-two one, in linear light for
// sRGB) trilinearly at the LOD of that footprint: the source at
// L + max(0, log2 rho), the atlas at L + max(0, -log2 rho), rho being the
// face's source texels per atlas texel along a side (Williams, "Pyramidal
// Parametrics", SIGGRAPH 1983; the GL spec's LOD rule). So level 0 is the
// coarser grid at full resolution and the finer one minified to it: where
// the two have the same density, the plain (magnified) surface PSNR. Both are
// compared at the points surface_error uses. The source's chain is built
// from the source with the texels no face reaches pull-push filled, so its
// own chart bleed is not counted against the atlas (texel_reach.h).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/encode/texture/texture_sampler.h"
#include "codec/encode/texture/warp_quality.h"

namespace gltfwarp {

constexpr int kMipLevels = 4;  // levels 0..3: a 4-texel gutter is one texel at level 2

struct MipQualityOptions {
  uint64_t max_points = 1'000'000;  // points per level at most (faces spread as surface_error)
  double worst_fraction = 0.01;     // the worst region: the worst patches holding this share of points
};

struct MipQuality {
  std::array<SurfaceError, kMipLevels> level;  // the mean at each level
  // Per level: the PSNR over the worst patches (groups of SurfaceUvs::
  // group_of_face, else faces) that together hold worst_fraction of the
  // points: the 99th-percentile patch error by default.
  std::array<double, kMipLevels> worst_psnr{};
  void add(const MipQuality& o);  // means only; worst regions take the lower
};

// The MIP chain of a sampler, level 0 first (`s` itself: move a temporary
// in, as a 4096² float level 0 is 256 MB), down to 1x1 or `levels` levels:
// box-filtered 2x2 means of the linear texels. An odd side drops its last
// texel, as a plain box generator does; GPUs differ there (a linear blit
// keeps the content in place but point-samples where its phase is whole),
// and no one rule is every viewer's.
std::vector<TextureSampler> mip_chain(TextureSampler s, int levels);

// The reference a viewer's MIP chain of the source gives: the source with
// the texels no face of `reach_faces` (source UVs, 6 floats per face)
// reaches filled from its charts (texel_reach.h), then mip_chain. Every page
// an image is warped into compares with the one reference, built from all
// the faces that show the image (a 4096² source's is seconds of work).
std::vector<TextureSampler> mip_reference(const TextureSampler& source, std::span<const float> reach_faces);

MipQuality mip_surface_error(std::span<const TextureSampler> reference, const TextureSampler& atlas,
                             std::span<const SurfaceUvs> prims, const MipQualityOptions& options = {});
// The same against the reference of prims' own source faces.
MipQuality mip_surface_error(const TextureSampler& source, const TextureSampler& atlas,
                             std::span<const SurfaceUvs> prims, const MipQualityOptions& options = {});

}  // namespace gltfwarp
