// EncodeOptions::quality_weight (encode --quality-weight): the encoder's
// quality measures weigh each face by its 3D area when asked, and then agree
// with `compare --weight area`, as they agree with `compare` per texel.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "codec/decode/decoder.h"
#include "codec/encode/encoder.h"
#include "codec/encode/texture/surface_compare.h"
#include "codec/encode/texture/warp_quality.h"
#include "format/gltf/gltf_io.h"
#include "tests/support/corpus.h"

namespace gltfwarp {
namespace {

// Two faces of equal UV area (1/8 of the image each) whose surfaces differ
// 1:4: per texel their points weigh alike; by area each face's points
// together weigh the texels its surface would hold, thinned or not.
TEST(QualityWeight, SampledFacesWeighTheirSurface) {
  const std::vector<float> uv = {0, 0, 0.5f, 0, 0, 0.5f, 0.5f, 0.5f, 1, 0.5f, 0.5f, 1};
  const std::vector<float> by_area = {0.05f, 0.2f};  // UV area at the mean density: 1:4
  constexpr double kTexels = 64.0 * 64.0;
  for (const uint64_t budget : {uint64_t(4'000'000), uint64_t(20)}) {
    SurfaceUvs per_texel{uv, uv, {}, {}};
    const FaceSampling plain = sample_faces({&per_texel, 1}, kTexels, budget);
    SurfaceUvs weighed{uv, uv, {}, by_area};
    const FaceSampling area = sample_faces({&weighed, 1}, kTexels, budget);
    ASSERT_EQ(area.side[0].size(), 2u);
    for (size_t f = 0; f < 2; ++f) {
      EXPECT_EQ(area.side[0][f], plain.side[0][f]) << "the points sampled do not change";
      const double points = double(area.side[0][f]) * area.side[0][f];
      EXPECT_NEAR(area.weight[0][f] * points, by_area[f] * kTexels, 1e-6 * kTexels) << "budget " << budget;
    }
    EXPECT_EQ(plain.weight[0][0], plain.weight[0][1]) << "per texel, equal UV areas weigh alike";
    EXPECT_NEAR(area.weight[0][1] / area.weight[0][0], 4.0, 1e-6);
  }
}

// The Duck puts many texels on its small eyes and beak. Encoded with the
// floor and goal by area, its atlas reads the quality it aims at (44 dB)
// where compare measures by area, and spends fewer texels there than the
// per-texel encode: the texel-weighted surface PSNR falls, the file shrinks.
TEST(QualityWeight, TheDuckByAreaReachesItsAimAsCompareMeasuresIt) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = test::corpus_path("Duck");
  ASSERT_FALSE(path.empty()) << "Duck is not in the corpus";
  tinygltf::Model source;
  ASSERT_TRUE(read_gltf(path, source).ok);
  const std::string dir = test::scratch_dir("quality_weight");
  double texel_psnr[2] = {0, 0}, area_psnr[2] = {0, 0};
  size_t bytes[2] = {0, 0};
  for (const QualityWeight weight : {QualityWeight::source_texel, QualityWeight::surface_area}) {
    const int w = weight == QualityWeight::surface_area;
    tinygltf::Model model = source;
    EncodeOptions o;
    o.quality_weight = weight;
    o.quality_fallback = false;  // keep the atlas, to measure it
    EncodeReport report;
    ASSERT_FALSE(encode_model(model, o, report).failed());
    ASSERT_EQ(report.atlases.size(), 1u);
    bytes[w] = report.atlases[0].atlas_image_bytes;
    DecodeReport dr;
    ASSERT_FALSE(decode_model(model, {}, dr).failed());
    const std::string out = dir + (w ? "/area.glb" : "/texel.glb");
    ASSERT_EQ(write_gltf(model, out), "");
    tinygltf::Model decoded;
    ASSERT_TRUE(read_gltf(out, decoded).ok);
    for (const SampleWeight measure : {SampleWeight::source_texel, SampleWeight::surface_area}) {
      SurfaceCompareOptions co;
      co.weight = measure;
      const SurfaceComparison c = compare_surface(source, decoded, co);
      ASSERT_TRUE(c.error.empty()) << c.error;
      (measure == SampleWeight::surface_area ? area_psnr : texel_psnr)[w] = c.psnr;
    }
    // The encoder's own figure is the one its weighting asks for.
    const double own = w ? area_psnr[w] : texel_psnr[w];
    EXPECT_NEAR(report.atlases[0].psnr, own, 0.5) << (w ? "by area" : "per texel");
    EXPECT_GE(own, 43.5) << "the default aim (44 dB), as compare measures it";
  }
  std::printf("Duck: per texel %zu B (%.1f dB per texel, %.1f by area); by area %zu B (%.1f, %.1f)\n",
              bytes[0], texel_psnr[0], area_psnr[0], bytes[1], texel_psnr[1], area_psnr[1]);
  EXPECT_LT(bytes[1], bytes[0]);
  EXPECT_LT(texel_psnr[1], texel_psnr[0]);
  EXPECT_GT(area_psnr[0], area_psnr[1] + 3.0)
      << "per texel, the eyes' texels lift the surface far above the aim";
}

}  // namespace
}  // namespace gltfwarp
