// sRGB transfer functions and the 8-bit table (see srgb.h).
#include "codec/encode/texture/srgb.h"

#include <bit>
#include <cmath>
#include <cstdint>

#include <OpenImageIO/imagebuf.h>

namespace gltfwarp {

float srgb_to_linear(float v) {
  if (v <= 0.04045f) return v / 12.92f;
  return std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float v) {
  if (v <= 0.0031308f) return 12.92f * v;
  return 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

// srgb_to_linear of the 256 floats an 8-bit channel becomes. The keys come
// from get_pixels itself (a 256x1 8-bit image): 126 of them differ from
// float(k) / 255.0f in the last bit, so a table keyed on that (or matched
// within a tolerance) would not give the formula's bits.
struct SrgbTable {
  float key[256], value[256];
};

const SrgbTable& srgb_table() {
  static const SrgbTable table = [] {
    SrgbTable t{};
    OIIO::ImageBuf bytes(OIIO::ImageSpec(256, 1, 1, OIIO::TypeDesc::UINT8));
    for (int i = 0; i < 256; ++i) {
      const float v = float(i) / 255.0f;
      bytes.setpixel(i, 0, &v);
    }
    bytes.get_pixels(bytes.roi(), OIIO::TypeDesc::FLOAT, t.key);
    for (int i = 0; i < 256; ++i) t.value[i] = srgb_to_linear(t.key[i]);
    return t;
  }();
  return table;
}

}  // namespace

float srgb_to_linear_of_pixel(float v) {
  const SrgbTable& t = srgb_table();
  const float scaled = v * 255.0f;
  if (scaled >= 0.0f && scaled <= 255.0f) {
    const int k = int(scaled + 0.5f);
    if (std::bit_cast<uint32_t>(t.key[k]) == std::bit_cast<uint32_t>(v)) return t.value[k];
  }
  return srgb_to_linear(v);
}

}  // namespace gltfwarp
