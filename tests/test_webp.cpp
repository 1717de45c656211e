// WebP output (issue 16, item 3): the coder in memory, and encodes that ask
// for it (or for JPEG): atlases, and the source images of a group that keeps explicit UVs,
// are WebP, named through EXT_texture_webp (declared required: there is no
// fallback image), and the Khronos validator accepts the files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "codec/encode/encoder.h"
#include "codec/encode/texture/image_io.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_materials.h"
#include "support/corpus.h"
#include "tests/support/testing/sample_model.h"

namespace gltfwarp {
namespace {

OIIO::ImageBuf smooth_image(int w, int h, int nch) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, nch, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nch; ++c) p[(size_t(y) * w + x) * nch + c] = uint8_t(40 + (x + y) / 2 + 30 * c);
  return buf;
}

double max_error(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, int nch) {
  const auto* pa = static_cast<const uint8_t*>(a.localpixels());
  const auto* pb = static_cast<const uint8_t*>(b.localpixels());
  const size_t n = size_t(a.spec().width) * a.spec().height;
  double err = 0;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < nch; ++c)
      err = std::max(err, std::abs(double(pa[i * a.spec().nchannels + c]) - pb[i * b.spec().nchannels + c]));
  return err;
}

TEST(WebP, RoundTripIsCloseAndQualityBuysBytes) {
  const OIIO::ImageBuf img = smooth_image(96, 64, 3);
  size_t previous = 0;
  for (const int q : {20, 60, 95}) {
    std::vector<uint8_t> bytes;
    std::string err;
    ASSERT_TRUE(encode_image(img, "image/webp", q, bytes, err)) << err;
    EXPECT_EQ(sniff_image_codec(bytes), ImageCodec::webp);
    DecodedImage dec;
    ASSERT_EQ(decode_image(bytes, dec), "");
    EXPECT_EQ(dec.codec, ImageCodec::webp);
    ASSERT_EQ(dec.pixels.spec().width, 96);
    ASSERT_EQ(dec.pixels.spec().height, 64);
    ASSERT_GE(dec.pixels.spec().nchannels, 3);
    EXPECT_LT(max_error(img, dec.pixels, 3), q >= 90 ? 8 : 24) << "quality " << q;
    EXPECT_GE(bytes.size(), previous) << "a higher quality never codes smaller (q" << q << ")";
    previous = bytes.size();
  }
}

TEST(WebP, KeepsAlphaAndPromotesGrey) {
  for (const int nch : {1, 2, 4}) {
    const OIIO::ImageBuf img = smooth_image(32, 24, nch);
    std::vector<uint8_t> bytes;
    std::string err;
    ASSERT_TRUE(encode_image(img, "image/webp", 90, bytes, err)) << err;
    DecodedImage dec;
    ASSERT_EQ(decode_image(bytes, dec), "");
    const bool alpha = nch == 2 || nch == 4;
    EXPECT_EQ(dec.pixels.spec().nchannels, alpha ? 4 : 3) << nch << " channels";
  }
}

// Every texture names a WebP image through EXT_texture_webp, and a PNG or
// JPEG image through `source`; the extension is declared used and required.
void expect_webp_textures_well_formed(const tinygltf::Model& m, size_t& webp_textures) {
  webp_textures = 0;
  for (size_t t = 0; t < m.textures.size(); ++t) {
    const int image = texture_image(m, int(t));
    ASSERT_GE(image, 0) << "texture " << t;
    const bool webp = m.images[size_t(image)].mimeType == "image/webp";
    EXPECT_EQ(webp, m.textures[t].source < 0) << "texture " << t;
    EXPECT_EQ(webp, m.textures[t].extensions.count("EXT_texture_webp") == 1) << "texture " << t;
    webp_textures += webp;
  }
  auto declared = [&](const std::vector<std::string>& list) {
    return std::find(list.begin(), list.end(), "EXT_texture_webp") != list.end();
  };
  EXPECT_EQ(declared(m.extensionsUsed), webp_textures > 0);
  EXPECT_EQ(declared(m.extensionsRequired), webp_textures > 0);
}

// Asked for WebP, a generated model's atlas is WebP whichever way the
// encoder decides (the atlas kept, or explicit UVs with the sources made
// WebP), and the files validate.
TEST(WebP, EncodedFilesNameTheirWebpImagesThroughTheExtension) {
  for (const bool keep_atlas : {true, false}) {
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model("sphere", 1500, 256, model), "");
    EncodeOptions o;
    o.image_format = "webp";
    o.image_quality = 80;
    o.quality_fallback = !keep_atlas;
    o.min_psnr = 0;  // the busy generated texture: no floor, so that the choice is by bytes
    EncodeReport report;
    ASSERT_EQ(encode_model(model, o, report).message, "");
    size_t webp_textures = 0;
    expect_webp_textures_well_formed(model, webp_textures);
    EXPECT_GT(webp_textures, 0u) << "WebP was asked for";
    for (const tinygltf::Image& img : model.images) EXPECT_EQ(img.mimeType, "image/webp") << img.name;
    for (const PrimitiveReport& p : report.primitives)
      std::printf("%s: %s, fallback reason %d\n", keep_atlas ? "atlas kept" : "encoder's choice",
                  p.handling == Handling::implicit_uv ? "implicit" : "explicit", int(p.fallback.reason));
    if (keep_atlas) {
      ASSERT_EQ(report.atlases.size(), 1u);
      const AtlasReport& a = report.atlases[0];
      // Measured on the decoded WebP bytes, and priced against the source
      // made WebP. The busy generated texture at q80 and the default
      // density: 29.0 dB (mixed layout), 30.1 (unfold); a misread atlas
      // measures below 20.
      EXPECT_GT(a.psnr, 25.0);
      EXPECT_GT(a.explicit_image_quality, 0);
      EXPECT_EQ(a.explicit_image_mime, "image/webp");
    }
    const std::string dir = test::scratch_dir("webp");
    const std::string path = dir + (keep_atlas ? "/atlas.glb" : "/chosen.glb");
    ASSERT_EQ(write_gltf(model, path), "");
    tinygltf::Model back;
    ASSERT_TRUE(read_gltf(path, back).ok);
    expect_webp_textures_well_formed(back, webp_textures);
    const test::ValidatorResult v = test::validate(path);
    if (!v.ran) {
      if (test::on_ci()) FAIL() << "gltf-validator is not installed (run scripts/install-deps)";
      GTEST_SKIP() << "gltf-validator not installed";
    }
    EXPECT_EQ(v.errors, 0) << v.raw;
    if (keep_atlas) {  // the decoder leaves the images as they are
      const std::string dec = dir + "/decoded.glb";
      std::string out;
      ASSERT_EQ(
          test::run_command(std::string(GLTFWARP_CLI) + " decode -q " + path + " -o " + dec + " 2>&1", &out),
          0)
          << out;
      const test::ValidatorResult vd = test::validate(dec);
      EXPECT_EQ(vd.errors, 0) << vd.raw;
    }
  }
}

// Asked for a lossy coder at a low quality, a group whose atlas stays below
// the quality floor keeps explicit UVs, and its source images still come
// out in the coder and quality asked, not as the PNG they were
// (TwoSidedPlane at JPEG q10 kept its 156 KB PNG).
TEST(WebP, BelowFloorFallbackWritesTheCoderAsked) {
  for (const std::string format : {"jpeg", "webp"}) {
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model("sphere", 1500, 256, model), "");
    EncodeOptions o;
    o.image_format = format;
    o.image_quality = 10;
    EncodeReport report;
    ASSERT_EQ(encode_model(model, o, report).message, "");
    bool below_floor = false;
    for (const PrimitiveReport& p : report.primitives)
      if (p.handling == Handling::fallback && p.fallback.reason == FallbackReason::below_quality_floor) {
        below_floor = true;
        EXPECT_EQ(p.fallback.images_recoded_quality, 10);
      }
    ASSERT_TRUE(below_floor) << "precondition: the busy texture at q10 stays below the floor (" << format
                             << ")";
    const std::string mime = "image/" + format;
    for (const tinygltf::Image& img : model.images) EXPECT_EQ(img.mimeType, mime) << img.name;
    size_t webp_textures = 0;
    expect_webp_textures_well_formed(model, webp_textures);
  }
}

}  // namespace
}  // namespace gltfwarp
