// The texels of a texture that some triangle's bilinear footprint reaches,
// and the texture with every other texel pull-push filled (atlas_fill.h).
//
// Why: a source texture's unused texels (between and around its UV charts)
// bleed into its charts at the MIP levels a minified view samples, as the
// source's own renders show (the CesiumMilkTruck's light tyre ring). That
// bleed is an artefact of the source's packing, not of its content, so the
// quality reference at MIP levels >= 1 is the source with those texels
// filled from the charts. Otherwise a yardstick rewards copying the bleed,
// and charges any re-parameterization (ours, or a better packing) for it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/encode/texture/texture_sampler.h"

namespace gltfwarp {

class TexelReach {
 public:
  TexelReach(int width, int height, OIIO::ImageBuf::WrapMode wrap_s, OIIO::ImageBuf::WrapMode wrap_t);
  explicit TexelReach(const TextureSampler& texture);

  // Marks the texels within 1.5 texels of each triangle (6 floats per face:
  // u0 v0 u1 v1 u2 v2), after `transform` (uv' = t0 u + t1 v + t2, t3 u + t4 v
  // + t5), wrapped as the sampler wraps. A triangle spanning more than the
  // texture (tiled UVs) marks every texel.
  void add_triangles(std::span<const float> uv_faces, const std::array<double, 6>& transform);

  uint64_t reached() const;
  bool all_reached() const { return all_; }

  // Pull-push fills the unreached texels of `texture` (float pixels, as
  // TextureSampler holds them); reached texels stay bit-identical.
  void fill_unreached(TextureSampler& texture) const;

 private:
  int w_ = 0, h_ = 0;
  OIIO::ImageBuf::WrapMode wrap_s_, wrap_t_;
  bool all_ = false;
  std::vector<uint8_t> reached_;  // w * h
};

// `texture` with the texels no face of `uv_faces` reaches filled (see above).
TextureSampler with_unreached_filled(const TextureSampler& texture, std::span<const float> uv_faces);

}  // namespace gltfwarp
