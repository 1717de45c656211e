// Loading a texture for sampling (codec/encode/texture/texture_sampler.h):
// the sRGB -> linear conversion of every texel, by table for 8-bit images,
// must give the bits srgb_to_linear gives, whatever the source's format.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "codec/encode/texture/srgb.h"
#include "codec/encode/texture/texture_sampler.h"

namespace gltfwarp {
namespace {

// Every texel of `raw` loaded as sRGB against srgb_to_linear of get_pixels'
// float (alpha as it is); the number of texels that differ in any bit.
int texels_off(const OIIO::ImageBuf& raw) {
  TextureSampler s;
  load_texture_sampler(raw, true, 33071, 33071, {1, 0, 0, 0, 1, 0}, s);
  const int w = raw.spec().width, h = raw.spec().height, nch = raw.spec().nchannels;
  std::vector<float> plain(size_t(w) * h * nch);
  raw.get_pixels(raw.roi(), OIIO::TypeDesc::FLOAT, plain.data());
  const auto* loaded = static_cast<const float*>(s.pixels.localpixels());
  int off = 0;
  for (size_t i = 0; i < plain.size(); ++i) {
    const float want = int(i % nch) < 3 ? srgb_to_linear(plain[i]) : plain[i];
    off += std::bit_cast<uint32_t>(want) != std::bit_cast<uint32_t>(loaded[i]);
  }
  return off;
}

TEST(TextureSampler, SrgbLoadGivesTheBitsOfSrgbToLinear) {
  // Every 8-bit value in every channel, alpha included.
  OIIO::ImageBuf bytes(OIIO::ImageSpec(256, 1, 4, OIIO::TypeDesc::UINT8));
  for (int i = 0; i < 256; ++i) {
    const float v[4] = {i / 255.0f, (255 - i) / 255.0f, ((i * 37) % 256) / 255.0f, i / 255.0f};
    bytes.setpixel(i, 0, v);
  }
  EXPECT_EQ(texels_off(bytes), 0);
  // 16-bit values between the 8-bit ones, and floats outside [0, 1], -0,
  // NaN and infinity: none may take an 8-bit value's result.
  OIIO::ImageBuf shorts(OIIO::ImageSpec(1024, 1, 3, OIIO::TypeDesc::UINT16));
  for (int i = 0; i < 1024; ++i) {
    const float v[3] = {i / 1023.0f, (i * 64 + 1) / 65535.0f, (65535 - i * 61) / 65535.0f};
    shorts.setpixel(i, 0, v);
  }
  EXPECT_EQ(texels_off(shorts), 0);
  const float odd[] = {-0.0f,
                       -1.0f,
                       1.5f,
                       255.0f,
                       0.5f / 255.0f,
                       std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(),
                       1e-30f,
                       0.9999999f};
  OIIO::ImageBuf floats(OIIO::ImageSpec(int(std::size(odd)), 1, 1, OIIO::TypeDesc::FLOAT));
  for (int i = 0; i < int(std::size(odd)); ++i) floats.setpixel(i, 0, &odd[i]);
  EXPECT_EQ(texels_off(floats), 0);
}

}  // namespace
}  // namespace gltfwarp
