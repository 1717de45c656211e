// What a minifying viewer shows of the truck's default encode: the
// encoder's own measure (the decoder's UVs, the file's texels) resampled at
// MIP levels 0-3 and compared with the source at the same footprint, over
// the whole surface and over its worst 1% (where a crack or a streak along
// a sliver, like the one the upper grille once had, would show).
#include <gtest/gtest.h>

#include <cstdio>

#include "codec/encode/encoder.h"
#include "format/gltf/gltf_io.h"
#include "support/corpus.h"

namespace gltfwarp {
namespace {

using test::corpus_models;

TEST(CorpusMinified, TruckHoldsItsQualityAtEveryMipLevel) {
  GLTFWARP_REQUIRE_CORPUS();
  std::string path;
  for (const auto& m : corpus_models())
    if (m.name == "CesiumMilkTruck") path = m.path;
  ASSERT_FALSE(path.empty());
  tinygltf::Model model;
  ASSERT_TRUE(read_gltf(path, model).ok);
  EncodeOptions o;
  o.quality_fallback = false;  // measure the atlas even where explicit UVs would be kept
  EncodeReport report;
  ASSERT_EQ(encode_model(model, o, report), "");
  ASSERT_EQ(report.atlases.size(), 1u);
  const AtlasReport& a = report.atlases[0];
  for (int l = 0; l < 4; ++l) {
    std::printf("truck mip %d: mean %.2f dB, worst 1%% %.2f dB\n", l, a.mip_psnr[l], a.worst_psnr[l]);
    EXPECT_GE(a.mip_psnr[l], 36.0) << "level " << l;
    EXPECT_GE(a.worst_psnr[l], 24.0) << "level " << l;
  }
}

}  // namespace
}  // namespace gltfwarp
