// A group that keeps explicit UVs writes its source PNGs again where our PNG
// writer codes the same pixels smaller, and its JPEGs with Huffman tables
// optimised for them (issue 16: the explicit-UV file a user compares with
// can have them too, so the encoder's comparison counts them).
#include <gtest/gtest.h>

#include <OpenImageIO/imagebufalgo.h>

#include "codec/encode/encoder.h"
#include "codec/encode/texture/image_io.h"
#include "support/generic_jpeg.h"
#include "support/malformed.h"

namespace gltfwarp {
namespace {

std::vector<uint8_t> our_png(int size) {
  OIIO::ImageBuf img(OIIO::ImageSpec(size, size, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(img.localpixels());
  for (int i = 0; i < size * size * 3; ++i) p[i] = uint8_t((i * 7) & 255);
  std::vector<uint8_t> bytes;
  EXPECT_EQ(encode_image(img, ImageEncodeOptions{}, bytes), "");
  return bytes;
}

// The chunk `type` with `data` (its CRC is not checked by the test's reader).
std::vector<uint8_t> chunk(const char* type, const std::string& data) {
  const uint32_t n = uint32_t(data.size());
  std::vector<uint8_t> c = {uint8_t(n >> 24), uint8_t(n >> 16), uint8_t(n >> 8), uint8_t(n)};
  c.insert(c.end(), type, type + 4);
  c.insert(c.end(), data.begin(), data.end());
  c.insert(c.end(), 4, 0);
  return c;
}

// The bytes the encoder wrote for `image` (it moves images into buffer views).
std::vector<uint8_t> written_bytes(const tinygltf::Model& m, size_t image) {
  const tinygltf::Image& im = m.images[image];
  if (!im.image.empty() || im.bufferView < 0) return im.image;
  const tinygltf::BufferView& bv = m.bufferViews[size_t(im.bufferView)];
  const auto& data = m.buffers[size_t(bv.buffer)].data;
  return {data.begin() + std::ptrdiff_t(bv.byteOffset),
          data.begin() + std::ptrdiff_t(bv.byteOffset + bv.byteLength)};
}

// A grid showing one 128² PNG (made by `add_image`), encoded with `o` under
// a floor no atlas reaches, so the group keeps explicit UVs: `source` gets
// the image's bytes before, `why` the fallback.
void encode_below_floor(tinygltf::Model& m, int (*add_image)(tinygltf::Model&, int), EncodeOptions o,
                        std::vector<uint8_t>& source, Fallback& why) {
  m = test::empty_scene();
  const int image = add_image(m, 128);
  test::add_primitive(m, test::grid_mesh(8, 8), test::add_material(m, test::add_texture(m, image)));
  source = m.images[size_t(image)].image;
  o.min_psnr = 99;
  o.goal_psnr = 0;
  EncodeReport report;
  ASSERT_EQ(encode_model(m, o, report).message, "");
  ASSERT_EQ(report.primitives.size(), 1u);
  why = report.primitives[0].fallback;
  ASSERT_EQ(why.reason, FallbackReason::below_quality_floor);
  ASSERT_EQ(m.images.size(), 1u);
}

TEST(LosslessRepack, OnlyPngsThatHoldPixelsAloneQualify) {
  const std::vector<uint8_t> png = our_png(16);
  std::string types;
  for (size_t at = 8; at + 12 <= png.size();) {
    types += std::string(reinterpret_cast<const char*>(&png[at + 4]), 4) + " ";
    at += 12 + (size_t(png[at]) << 24 | size_t(png[at + 1]) << 16 | size_t(png[at + 2]) << 8 | png[at + 3]);
  }
  EXPECT_TRUE(png_holds_only_pixels(png)) << types;
  // A text chunk (or a colour profile) before IEND would be lost by re-encoding.
  for (const char* type : {"tEXt", "iCCP", "gAMA"}) {
    std::vector<uint8_t> with = png;
    const std::vector<uint8_t> extra = chunk(type, "Author\0x");
    with.insert(with.end() - 12, extra.begin(), extra.end());
    EXPECT_FALSE(png_holds_only_pixels(with)) << type;
  }
  for (size_t cut : {size_t(4), size_t(20), png.size() - 1}) {
    const std::vector<uint8_t> truncated(png.begin(), png.begin() + std::ptrdiff_t(cut));
    EXPECT_FALSE(png_holds_only_pixels(truncated)) << cut;
  }
  std::vector<uint8_t> trailing = png;
  trailing.push_back(0);
  EXPECT_FALSE(png_holds_only_pixels(trailing));
  std::vector<uint8_t> jpeg;
  std::string err;
  OIIO::ImageBuf img;
  ASSERT_TRUE(decode_image(png, img, err)) << err;
  ASSERT_TRUE(encode_image(img, "image/jpeg", 80, jpeg, err)) << err;
  EXPECT_FALSE(png_holds_only_pixels(jpeg));
}

TEST(LosslessRepack, FallbackWritesSmallerPngsOfTheSamePixels) {
  tinygltf::Model m;
  std::vector<uint8_t> source;
  Fallback why;
  // stb's PNG writer (add_png_image's): larger than ours.
  encode_below_floor(m, test::add_png_image, EncodeOptions{}, source, why);
  if (HasFatalFailure()) return;
  EXPECT_EQ(why.images_repacked, 1u);
  EXPECT_EQ(why.repacked_bytes_before, source.size());
  const std::vector<uint8_t> written = written_bytes(m, 0);
  EXPECT_EQ(why.repacked_bytes_after, written.size());
  EXPECT_LT(written.size(), source.size());
  EXPECT_EQ(m.images[0].mimeType, "image/png");
  OIIO::ImageBuf before, after;
  std::string err;
  ASSERT_TRUE(decode_image(source, before, err)) << err;
  ASSERT_TRUE(decode_image(written, after, err)) << err;
  ASSERT_EQ(after.spec().nchannels, before.spec().nchannels);
  ASSERT_EQ(after.spec().format, before.spec().format);
  EXPECT_EQ(OIIO::ImageBufAlgo::compare(after, before, 0.0f, 0.0f).maxerror, 0.0);
}

// Asked for JPEG, a group that keeps explicit UVs still writes a source
// image as it was where JPEG would not make it smaller: the coder could only
// lose quality (the Fox at JPEG q85 came out 153.5 KB at 39.5 dB, against
// 110.6 KB at 52.1 dB with its own PNG: bench at 689e4e2).
TEST(LosslessRepack, FallbackKeepsASourceTheAskedCoderWouldNotShrink) {
  for (const bool flat : {true, false}) {
    EncodeOptions o;
    o.image_format = "jpeg";
    o.image_quality = 85;
    tinygltf::Model m;
    std::vector<uint8_t> source;
    Fallback why;
    encode_below_floor(m, flat ? test::add_flat_png_image : test::add_png_image, o, source, why);
    if (HasFatalFailure()) return;
    const tinygltf::Image& im = m.images[0];
    const std::vector<uint8_t> written = written_bytes(m, 0);
    if (flat) {  // JPEG only adds bytes: the PNG stays, byte for byte
      EXPECT_EQ(why.images_kept, 1u);
      EXPECT_EQ(why.images_recoded_quality, 0);
      EXPECT_EQ(why.kept_bytes, source.size());
      EXPECT_GE(why.kept_recoded_bytes, source.size());
      EXPECT_EQ(why.kept_recoded_quality, 85);
      EXPECT_EQ(im.mimeType, "image/png");
      EXPECT_EQ(written, source);
    } else {  // the busy checker: JPEG q85 is the smaller file, as asked
      EXPECT_EQ(why.images_kept, 0u);
      EXPECT_EQ(why.images_recoded_quality, 85);
      EXPECT_EQ(im.mimeType, "image/jpeg");
      EXPECT_LT(written.size(), source.size());
    }
  }
}

// add_gradient_png_image's pixels as a JPEG q90 with libjpeg's generic
// tables, as most tools write one.
int add_generic_jpeg_image(tinygltf::Model& m, int size) {
  const int image = test::add_gradient_png_image(m, size);
  OIIO::ImageBuf pixels;
  std::string err;
  EXPECT_TRUE(decode_image(m.images[size_t(image)].image, pixels, err)) << err;
  m.images[size_t(image)].image = test::generic_jpeg(pixels, 90);
  m.images[size_t(image)].mimeType = "image/jpeg";
  return image;
}

// Kept as it is (the default --image-format keep), a source JPEG is kept in
// fewer bytes: its coefficients re-coded with optimised tables, every pixel
// the same.
TEST(LosslessRepack, FallbackWritesSourceJpegsWithOptimisedTablesToTheSamePixels) {
  tinygltf::Model m;
  std::vector<uint8_t> source;
  Fallback why;
  encode_below_floor(m, add_generic_jpeg_image, EncodeOptions{}, source, why);
  if (HasFatalFailure()) return;
  ASSERT_EQ(sniff_image_codec(source), ImageCodec::jpeg);
  EXPECT_EQ(why.images_repacked, 1u);
  EXPECT_EQ(why.images_recoded_quality, 0);
  const std::vector<uint8_t> written = written_bytes(m, 0);
  EXPECT_EQ(why.repacked_bytes_before, source.size());
  EXPECT_EQ(why.repacked_bytes_after, written.size());
  EXPECT_LT(written.size(), source.size());
  EXPECT_EQ(m.images[0].mimeType, "image/jpeg");
  EXPECT_EQ(sniff_image_codec(written), ImageCodec::jpeg);
  OIIO::ImageBuf before, after;
  std::string err;
  ASSERT_TRUE(decode_image(source, before, err)) << err;
  ASSERT_TRUE(decode_image(written, after, err)) << err;
  EXPECT_EQ(OIIO::ImageBufAlgo::compare(after, before, 0.0f, 0.0f).maxerror, 0.0);
}

// Asked for JPEG q30, the same group writes the source re-encoded at q30 (the
// smaller file, as asked), not the lossless re-coding of its q90: the one
// must not overwrite the other.
TEST(LosslessRepack, ARecodeAsAskedIsNotOverwrittenByTheLosslessOne) {
  EncodeOptions o;
  o.image_format = "jpeg";
  o.image_quality = 30;
  tinygltf::Model m;
  std::vector<uint8_t> source;
  Fallback why;
  encode_below_floor(m, add_generic_jpeg_image, o, source, why);
  if (HasFatalFailure()) return;
  EXPECT_EQ(why.images_recoded_quality, 30);
  EXPECT_EQ(why.images_repacked, 0u);
  const std::vector<uint8_t> written = written_bytes(m, 0);
  EXPECT_EQ(estimate_jpeg_quality(written), 30);
  EXPECT_EQ(m.images[0].mimeType, "image/jpeg");
}

}  // namespace
}  // namespace gltfwarp
