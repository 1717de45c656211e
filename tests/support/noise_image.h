// A w x w RGB 8-bit image of uniform noise from a seed: detail at every
// scale, so any resampling or fill difference shows in a quality measure.
#pragma once

#include <cstdint>

#include <OpenImageIO/imagebuf.h>

namespace gltfwarp::test {

inline OIIO::ImageBuf noise_image(int n, uint32_t seed) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(n, n, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (size_t i = 0; i < size_t(n) * n * 3; ++i) p[i] = uint8_t((seed = seed * 1664525u + 1013904223u) >> 24);
  return buf;
}

}  // namespace gltfwarp::test
