// Indexed PNG: the palette of an indexed source is read back exactly, and an
// atlas written with it holds only palette colours, each texel the nearest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/png_palette.h"

namespace gltfwarp {
namespace {

OIIO::ImageBuf rgb_image(int w, int h, const std::vector<PaletteEntry>& colours, int jitter) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const PaletteEntry& c = colours[size_t(x / 4 + y) % colours.size()];
      for (int k = 0; k < 3; ++k)
        p[(size_t(y) * w + x) * 3 + k] = uint8_t(std::clamp(c[k] + (x % 3 - 1) * jitter, 0, 255));
    }
  return buf;
}

const std::vector<PaletteEntry> kPalette = {
    {0, 0, 0, 255}, {250, 10, 10, 255}, {10, 200, 30, 255}, {40, 40, 220, 255}, {255, 255, 255, 255}};

TEST(PngPalette, IndexedRoundTripKeepsThePaletteAndSnapsToNearest) {
  // Texels a few steps off their colour come back as exactly that colour.
  const OIIO::ImageBuf img = rgb_image(33, 17, kPalette, 3);
  std::vector<uint8_t> bytes;
  ASSERT_EQ(encode_indexed_png(img, kPalette, bytes), "");
  ASSERT_GE(bytes.size(), 26u);
  EXPECT_EQ(bytes[25], 3) << "colour type 3 (indexed)";
  const std::vector<PaletteEntry> back = png_palette(bytes);
  EXPECT_EQ(back, kPalette);
  OIIO::ImageBuf dec;
  std::string err;
  ASSERT_TRUE(decode_image(bytes, dec, err)) << err;
  const OIIO::ImageBuf exact = rgb_image(33, 17, kPalette, 0);
  const auto* a = static_cast<const uint8_t*>(exact.localpixels());
  std::vector<uint8_t> b(size_t(33) * 17 * 3);
  dec.get_pixels(dec.roi(), OIIO::TypeDesc::UINT8, b.data());
  EXPECT_EQ(0, std::memcmp(a, b.data(), b.size()));
}

TEST(PngPalette, TruecolourJpegAndGarbageHaveNoPalette) {
  const OIIO::ImageBuf img = rgb_image(8, 8, kPalette, 0);
  std::vector<uint8_t> png, jpeg;
  ASSERT_EQ(encode_image(img, ImageEncodeOptions{}, png), "");
  ImageEncodeOptions jo;
  jo.codec = ImageCodec::jpeg;
  ASSERT_EQ(encode_image(img, jo, jpeg), "");
  EXPECT_TRUE(png_palette(png).empty());
  EXPECT_TRUE(png_palette(jpeg).empty());
  std::vector<uint8_t> indexed;
  ASSERT_EQ(encode_indexed_png(img, kPalette, indexed), "");
  indexed.resize(indexed.size() / 2);  // truncated: no crash, no palette
  EXPECT_TRUE(png_palette(indexed).empty());
  EXPECT_TRUE(png_palette({}).empty());
}

TEST(PngPalette, TranslucentEntriesKeepTheirAlpha) {
  const std::vector<PaletteEntry> pal = {{255, 0, 0, 255}, {0, 0, 255, 64}};
  OIIO::ImageBuf img(OIIO::ImageSpec(4, 2, 4, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(img.localpixels());
  for (int i = 0; i < 8; ++i) std::copy(pal[size_t(i % 2)].begin(), pal[size_t(i % 2)].end(), p + 4 * i);
  std::vector<uint8_t> bytes;
  ASSERT_EQ(encode_indexed_png(img, pal, bytes), "");
  EXPECT_EQ(png_palette(bytes), pal);
}

TEST(PngPalette, FlatArtGivesItsMostFrequentColoursAndGradientsNone) {
  // Five flat colours in stripes of unequal width, plus 1 texel in 400 of noise.
  const int w = 200, h = 100;
  OIIO::ImageBuf art(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(art.localpixels());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t stripe = x < 80 ? 0 : x < 130 ? 1 : x < 165 ? 2 : x < 190 ? 3 : 4;
      uint8_t* t = p + (size_t(y) * w + x) * 3;
      std::copy_n(kPalette[stripe].begin(), 3, t);
      if ((x * 7 + y * 13) % 400 == 0) t[0] = uint8_t(x), t[1] = uint8_t(y), t[2] = 77;
    }
  const std::vector<PaletteEntry> pal = dominant_colours(art, 0.99, 256);
  ASSERT_GE(pal.size(), 5u);
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(pal[i], kPalette[i]) << "most frequent first, entry " << i;
  EXPECT_TRUE(dominant_colours(art, 0.99, 5).size() == 5) << "99.75% covered by the five";
  EXPECT_TRUE(dominant_colours(art, 0.999, 5).empty()) << "the noise is more than 0.1%";

  OIIO::ImageBuf ramp(OIIO::ImageSpec(256, 64, 3, OIIO::TypeDesc::UINT8));  // 16,384 colours, one texel each
  auto* r = static_cast<uint8_t*>(ramp.localpixels());
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 256; ++x)
      r[(size_t(y) * 256 + x) * 3] = uint8_t(x), r[(size_t(y) * 256 + x) * 3 + 1] = uint8_t(y * 4);
  EXPECT_TRUE(dominant_colours(ramp).empty());
  EXPECT_TRUE(dominant_colours(OIIO::ImageBuf()).empty());
}

TEST(PngPalette, SnappedImageIsExactlyWhatTheIndexedPngDecodesTo) {
  OIIO::ImageBuf img = rgb_image(41, 23, kPalette, 5);
  snap_to_palette(img, kPalette);
  const auto* s = static_cast<const uint8_t*>(img.localpixels());
  for (size_t i = 0; i < size_t(41) * 23; ++i)
    EXPECT_TRUE(
        std::any_of(kPalette.begin(), kPalette.end(),
                    [&](const PaletteEntry& e) { return std::equal(e.begin(), e.begin() + 3, s + 3 * i); }))
        << "texel " << i << " is not a palette colour";
  std::vector<uint8_t> bytes;
  ASSERT_EQ(encode_indexed_png(img, kPalette, bytes), "");
  OIIO::ImageBuf dec;
  std::string err;
  ASSERT_TRUE(decode_image(bytes, dec, err)) << err;
  std::vector<uint8_t> b(size_t(41) * 23 * 3);
  dec.get_pixels(dec.roi(), OIIO::TypeDesc::UINT8, b.data());
  EXPECT_EQ(0, std::memcmp(s, b.data(), b.size()));
}

}  // namespace
}  // namespace gltfwarp
