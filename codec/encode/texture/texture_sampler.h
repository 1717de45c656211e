// A glTF texture as a viewer samples it when magnifying: bilinear, in linear
// light for sRGB slots (as GPUs filter sRGB textures), with the sampler's
// wrap mode applied per axis to texel indices as a GPU does, and the slot's
// KHR_texture_transform. Used to measure
// quality on the surface (surface_compare.h, warp_quality.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>

#include <OpenImageIO/imagebuf.h>

#include "format/gltf/gltf_materials.h"

namespace gltfwarp {

// A texel index wrapped as a GPU sampler wraps it: per axis, per texel, so
// bilinear at a REPEAT edge blends the last texel with the first.
int wrap_texel_index(long i, int n, OIIO::ImageBuf::WrapMode w);

struct TextureSampler {
  OIIO::ImageBuf pixels;  // float, local, origin 0; colour channels in linear light for sRGB slots
  OIIO::ImageBuf::WrapMode wrap_s = OIIO::ImageBuf::WrapPeriodic, wrap_t = OIIO::ImageBuf::WrapPeriodic;
  bool srgb = false;
  std::array<double, 6> transform{1, 0, 0, 0, 1, 0};  // uv' = (t0 u + t1 v + t2, t3 u + t4 v + t5)
  bool ok = false;

  int channels() const { return pixels.initialized() ? pixels.nchannels() : 0; }
  // The value at texture coordinate (u, v), transform applied, 0..1 on the
  // stored scale (sRGB channels re-encoded). `out` holds channels() floats.
  void sample(double u, double v, float* out) const;
};

// From encoded image bytes (PNG, JPEG, ...) or decoded pixels. gl_wrap_* are
// glTF sampler enums (10497 repeat, 33648 mirrored, 33071 clamp).
std::string load_texture_sampler(std::span<const uint8_t> image_bytes, bool srgb, int gl_wrap_s,
                                 int gl_wrap_t, const std::array<double, 6>& transform, TextureSampler& out);
// A material slot's texture as a viewer samples it: its image, its
// sampler's wrap modes, the slot's colour space and transform.
std::string load_slot_sampler(const tinygltf::Model& model, const TextureSlot& slot, TextureSampler& out);
void load_texture_sampler(const OIIO::ImageBuf& image, bool srgb, int gl_wrap_s, int gl_wrap_t,
                          const std::array<double, 6>& transform, TextureSampler& out);

// Points per triangle side so that a face covering `texel_area` source texels
// gets about one sample per texel (n x n subdivision, 2 <= n <= 64).
inline int surface_points_per_side(double texel_area) {
  if (!(texel_area > 0) || !std::isfinite(texel_area)) return 2;
  return std::clamp(int(std::ceil(std::sqrt(texel_area))), 2, 64);
}

// Calls visit(b0, b1, b2) at the centroids of the n^2 sub-triangles of an
// n x n barycentric subdivision: even coverage, never on an edge.
template <class Visit>
void for_each_surface_point(int n, Visit&& visit) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      double b1 = (i + 1.0 / 3) / n, b2 = (j + 1.0 / 3) / n;
      visit(1 - b1 - b2, b1, b2);
      if (i + j < n - 1) {
        b1 = (i + 2.0 / 3) / n, b2 = (j + 2.0 / 3) / n;
        visit(1 - b1 - b2, b1, b2);
      }
    }
}

}  // namespace gltfwarp
