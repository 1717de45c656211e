// Image I/O: PNG and JPEG round trips in memory, errors for bytes OIIO cannot
// decode, and the libjpeg writer against OpenImageIO's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/jpeg_writer.h"
#include "support/generic_jpeg.h"

namespace gltfwarp {
namespace {

OIIO::ImageBuf gradient(int w, int h, int nch) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, nch, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nch; ++c)
        p[(size_t(y) * w + x) * nch + c] = uint8_t((x * 3 + y * 5 + c * 40) & 255);
  return buf;
}

TEST(ImageIo, PngRoundTripIsExact) {
  for (int nch : {1, 2, 3, 4}) {
    const OIIO::ImageBuf img = gradient(37, 21, nch);
    std::vector<uint8_t> bytes;
    ASSERT_EQ(encode_image(img, ImageEncodeOptions{}, bytes), "");
    EXPECT_EQ(sniff_image_codec(bytes), ImageCodec::png);
    DecodedImage dec;
    ASSERT_EQ(decode_image(bytes, dec), "");
    ASSERT_EQ(dec.pixels.spec().width, 37);
    ASSERT_EQ(dec.pixels.spec().height, 21);
    ASSERT_EQ(dec.pixels.spec().nchannels, nch);
    EXPECT_EQ(dec.codec, ImageCodec::png);
    const auto* a = static_cast<const uint8_t*>(img.localpixels());
    const auto* b = static_cast<const uint8_t*>(dec.pixels.localpixels());
    EXPECT_EQ(0, std::memcmp(a, b, size_t(37) * 21 * nch)) << nch << " channels";
  }
}

TEST(ImageIo, JpegRoundTripIsCloseAndQualityIsEstimated) {
  // A smooth image, so JPEG at high quality is close.
  OIIO::ImageBuf img(OIIO::ImageSpec(64, 48, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(img.localpixels());
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) p[(y * 64 + x) * 3 + c] = uint8_t(60 + x + y + 20 * c);
  for (int q : {50, 75, 92}) {
    ImageEncodeOptions opt;
    opt.codec = ImageCodec::jpeg;
    opt.quality = q;
    std::vector<uint8_t> bytes;
    ASSERT_EQ(encode_image(img, opt, bytes), "");
    EXPECT_EQ(sniff_image_codec(bytes), ImageCodec::jpeg);
    EXPECT_NEAR(estimate_jpeg_quality(bytes), q, 2);
    DecodedImage dec;
    ASSERT_EQ(decode_image(bytes, dec), "");
    EXPECT_EQ(dec.codec, ImageCodec::jpeg);
    EXPECT_NEAR(dec.jpeg_quality, q, 2);
    ASSERT_EQ(dec.pixels.spec().nchannels, 3);
    const auto* b = static_cast<const uint8_t*>(dec.pixels.localpixels());
    double err = 0;
    for (size_t i = 0; i < size_t(64) * 48 * 3; ++i) err = std::max(err, std::abs(double(p[i]) - b[i]));
    EXPECT_LT(err, q >= 90 ? 6 : 16) << "quality " << q;
  }
}

// 203 x 117 (partial blocks at both edges): a gradient on the left, noise on the right.
OIIO::ImageBuf half_noise(int nch) {
  std::mt19937 rng(5);
  OIIO::ImageBuf img(OIIO::ImageSpec(203, 117, nch, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(img.localpixels());
  for (int y = 0; y < 117; ++y)
    for (int x = 0; x < 203; ++x)
      for (int c = 0; c < nch; ++c)
        p[(size_t(y) * 203 + x) * nch + c] =
            uint8_t((x < 100 ? (x * 2 + y + 30 * c) : int(rng() % 256)) & 255);
  return img;
}

// Optimised Huffman tables change only the entropy code: every pixel decodes
// the same as from OIIO's writer (as the encoder used it before
// jpeg_writer.h) at the same quality, and the file is smaller.
TEST(ImageIo, JpegWriterDecodesToTheSamePixelsAsOiiosInFewerBytes) {
  for (const int nch : {1, 3}) {
    const OIIO::ImageBuf img = half_noise(nch);
    for (const int q : {10, 50, 90}) {
      SCOPED_TRACE(std::to_string(nch) + " channels, quality " + std::to_string(q));
      ImageEncodeOptions opt;
      opt.codec = ImageCodec::jpeg;
      opt.quality = q;
      std::vector<uint8_t> ours;
      ASSERT_EQ(encode_image(img, opt, ours), "");
      const std::vector<uint8_t> theirs = test::generic_jpeg(img, q);
      EXPECT_LT(ours.size(), theirs.size());
      DecodedImage a, b;
      ASSERT_EQ(decode_image(ours, a), "");
      ASSERT_EQ(decode_image(theirs, b), "");
      ASSERT_EQ(a.pixels.spec().nchannels, nch);
      ASSERT_EQ(b.pixels.spec().nchannels, nch);
      EXPECT_EQ(0, std::memcmp(a.pixels.localpixels(), b.pixels.localpixels(), size_t(203) * 117 * nch));
      EXPECT_EQ(a.jpeg_quality, b.jpeg_quality);
    }
  }
}

TEST(ImageIo, JpegWriterRejectsWhatJpegCannotHold) {
  std::vector<uint8_t> bytes{1, 2, 3};
  const std::vector<uint8_t> px(8 * 8 * 4, 128);
  EXPECT_NE(encode_jpeg(px, 8, 8, 4, 80, bytes), "");  // alpha: the caller drops it first
  EXPECT_TRUE(bytes.empty());
  EXPECT_NE(encode_jpeg(std::span(px).first(8 * 8 * 2), 8, 8, 2, 80, bytes), "");
  EXPECT_NE(encode_jpeg(px, 0, 8, 3, 80, bytes), "");
  EXPECT_NE(encode_jpeg(px, 70000, 1, 3, 80, bytes), "");                           // beyond JPEG's 65500
  EXPECT_NE(encode_jpeg(std::span(px).first(10), 8, 8, 3, 80, bytes), "");          // too few pixels
  EXPECT_EQ(encode_jpeg(std::span(px).first(8 * 8 * 3), 8, 8, 3, 500, bytes), "");  // quality clamped
  EXPECT_EQ(sniff_image_codec(bytes), ImageCodec::jpeg);
}

TEST(ImageIo, JpegDropsAlpha) {
  const OIIO::ImageBuf img = gradient(16, 16, 4);
  ImageEncodeOptions opt;
  opt.codec = ImageCodec::jpeg;
  std::vector<uint8_t> bytes;
  ASSERT_EQ(encode_image(img, opt, bytes), "");
  DecodedImage dec;
  ASSERT_EQ(decode_image(bytes, dec), "");
  EXPECT_EQ(dec.pixels.spec().nchannels, 3);
}

TEST(ImageIo, SizeAndConvenienceForms) {
  const OIIO::ImageBuf img = gradient(40, 24, 3);
  std::vector<uint8_t> bytes;
  std::string err;
  ASSERT_TRUE(encode_image(img, "image/jpeg", 85, bytes, err)) << err;
  EXPECT_EQ(sniff_image_codec(bytes), ImageCodec::jpeg);
  int w = 0, h = 0;
  ASSERT_TRUE(image_size(bytes, w, h, err)) << err;
  EXPECT_EQ(w, 40);
  EXPECT_EQ(h, 24);
  OIIO::ImageBuf back;
  ASSERT_TRUE(decode_image(bytes, back, err)) << err;
  EXPECT_EQ(back.spec().width, 40);
  ASSERT_TRUE(encode_image(img, "image/png", 0, bytes, err)) << err;
  EXPECT_EQ(sniff_image_codec(bytes), ImageCodec::png);
  const std::vector<uint8_t> junk(64, 0x42);
  EXPECT_FALSE(image_size(junk, w, h, err));
  EXPECT_FALSE(err.empty());
  EXPECT_FALSE(decode_image(junk, back, err));
}

TEST(ImageIo, GarbageAndKtx2GiveErrors) {
  DecodedImage dec;
  const std::vector<uint8_t> empty;
  EXPECT_NE(decode_image(empty, dec), "");
  std::vector<uint8_t> garbage(1000);
  for (size_t i = 0; i < garbage.size(); ++i) garbage[i] = uint8_t(i * 7919 % 251);
  EXPECT_NE(decode_image(garbage, dec), "");
  // A PNG signature followed by garbage.
  std::vector<uint8_t> bad_png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A, 0, 0, 0, 13, 'I', 'H'};
  bad_png.insert(bad_png.end(), garbage.begin(), garbage.begin() + 100);
  EXPECT_NE(decode_image(bad_png, dec), "");
  // A truncated real PNG.
  std::vector<uint8_t> bytes;
  ASSERT_EQ(encode_image(gradient(32, 32, 3), ImageEncodeOptions{}, bytes), "");
  bytes.resize(bytes.size() / 2);
  EXPECT_NE(decode_image(bytes, dec), "");
  std::vector<uint8_t> ktx2 = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A, 0, 0};
  EXPECT_EQ(sniff_image_codec(ktx2), ImageCodec::ktx2);
  const std::string e = decode_image(ktx2, dec);
  EXPECT_NE(e.find("KTX2"), std::string::npos) << e;
}

// A JPEG's segments before its first scan (APPn, COM), as marker and payload, in order.
std::vector<std::pair<int, std::vector<uint8_t>>> metadata_segments(const std::vector<uint8_t>& b) {
  std::vector<std::pair<int, std::vector<uint8_t>>> out;
  for (size_t i = 2; i + 4 <= b.size() && b[i] == 0xFF && b[i + 1] != 0xDA;) {
    const size_t len = size_t(b[i + 2]) << 8 | b[i + 3];
    if ((b[i + 1] >= 0xE0 && b[i + 1] <= 0xEF) || b[i + 1] == 0xFE)
      out.emplace_back(b[i + 1],
                       std::vector<uint8_t>(b.begin() + std::ptrdiff_t(i + 4),
                                            b.begin() + std::ptrdiff_t(std::min(b.size(), i + 2 + len))));
    i += 2 + len;
  }
  return out;
}

// `jpeg` with a segment (marker, payload) inserted after its first segment (JFIF's APP0).
void insert_segment(std::vector<uint8_t>& jpeg, int marker, const std::string& payload) {
  const size_t at = 4 + (size_t(jpeg[4]) << 8 | jpeg[5]);
  const size_t len = payload.size() + 2;
  std::vector<uint8_t> seg = {0xFF, uint8_t(marker), uint8_t(len >> 8), uint8_t(len)};
  seg.insert(seg.end(), payload.begin(), payload.end());
  jpeg.insert(jpeg.begin() + std::ptrdiff_t(at), seg.begin(), seg.end());
}

bool has_marker(const std::vector<uint8_t>& b, uint8_t marker) {
  for (size_t i = 0; i + 1 < b.size(); ++i)
    if (b[i] == 0xFF && b[i + 1] == marker) return true;
  return false;
}

// jpegtran -optimize, in process: the same pixels from fewer bytes, with the
// source's EXIF, ICC profile and comment segments carried over in order, and
// a progressive source coming out as one baseline scan.
TEST(ImageIo, JpegLosslessRecodeKeepsPixelsAndSegmentsInFewerBytes) {
  for (const int nch : {1, 3})
    for (const bool progressive : {false, true}) {
      SCOPED_TRACE(std::to_string(nch) + " channels" + (progressive ? ", progressive" : ""));
      std::vector<uint8_t> source = test::generic_jpeg(half_noise(nch), 80, progressive);
      ASSERT_FALSE(source.empty());
      ASSERT_EQ(has_marker(source, 0xC2), progressive);  // SOF2: the writer did as asked
      insert_segment(source, 0xFE, "made by a test");
      insert_segment(source, 0xE2, std::string("ICC_PROFILE\0\1\1", 14) + std::string(300, 'p'));
      insert_segment(source, 0xE1, std::string("Exif\0\0", 6) + std::string(100, 'e'));
      std::vector<uint8_t> recoded;
      ASSERT_EQ(recode_jpeg_losslessly(source, recoded), "");
      if (!progressive) {
        EXPECT_LT(recoded.size(), source.size());
      }
      EXPECT_FALSE(has_marker(recoded, 0xC2));
      EXPECT_EQ(metadata_segments(recoded), metadata_segments(source));
      ASSERT_GE(metadata_segments(source).size(), 4u);  // JFIF, EXIF, ICC, comment (and what OIIO adds)
      DecodedImage a, b;
      ASSERT_EQ(decode_image(source, a), "");
      ASSERT_EQ(decode_image(recoded, b), "");
      ASSERT_EQ(b.pixels.spec().nchannels, nch);
      EXPECT_EQ(0, std::memcmp(a.pixels.localpixels(), b.pixels.localpixels(), size_t(203) * 117 * nch));
    }
}

// What is not a whole JPEG stays as it is: a one-line error, no bytes, no crash.
TEST(ImageIo, JpegLosslessRecodeRefusesDamagedData) {
  const std::vector<uint8_t> good = test::generic_jpeg(half_noise(3), 80);
  std::vector<std::vector<uint8_t>> bad = {
      {}, {0xFF, 0xD8}, std::vector<uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(good.size() / 2))};
  std::vector<uint8_t> flipped = good;
  for (size_t i = flipped.size() / 2; i < flipped.size() - 2; i += 7) flipped[i] ^= 0x5A;
  bad.push_back(flipped);
  bad.push_back(std::vector<uint8_t>(good.begin(), good.begin() + 20));
  for (size_t k = 0; k < bad.size(); ++k) {
    std::vector<uint8_t> out = {1};
    const std::string err = recode_jpeg_losslessly(bad[k], out);
    EXPECT_NE(err, "") << k;
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    EXPECT_TRUE(out.empty()) << k;
  }
}

}  // namespace
}  // namespace gltfwarp
