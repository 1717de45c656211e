// compare_surface's two weightings (SampleWeight): where a model's source
// density is even they agree, and where it is not, each weighs the faces as
// it says (texels or 3D area).
#include <gtest/gtest.h>

#include <cmath>

#include "codec/encode/texture/surface_compare.h"
#include "format/gltf/gltf_io.h"
#include "tests/support/corpus.h"
#include "tests/support/malformed.h"

namespace gltfwarp {
namespace {

using test::MeshSpec;

// Two flat quads side by side, each given half of the image (u in [0, 0.5]
// and [0.5, 1]); the second is `narrow` as wide in 3D as the first. In the
// decoded copy, the quad `shifted` (0 or 1) reads its texels a quarter of
// the image to the side: the only error. With `collinear`, every corner is
// moved onto the x axis (each to its own point): no face has area. Written
// and read back, as compare_surface reads images decoded.
void two_quads(float narrow, int shifted, tinygltf::Model& source, tinygltf::Model& decoded,
               bool collinear = false) {
  const std::string dir = test::scratch_dir("surface_compare");
  for (int side = 0; side < 2; ++side) {
    tinygltf::Model m = test::empty_scene();
    const int material = test::add_material(m, test::add_texture(m, test::add_gradient_png_image(m, 64)));
    MeshSpec spec;
    const float x[3] = {0, 1, 1 + narrow};
    for (int q = 0; q < 2; ++q) {
      const float du = side == 1 && q == shifted ? 0.25f : 0.0f;
      const uint32_t base = uint32_t(spec.positions.size() / 3);
      for (int c = 0; c < 4; ++c) {
        const int i = c & 1, j = c >> 1;
        spec.positions.insert(spec.positions.end(),
                              {x[q + i] + (collinear ? 10.0f * j : 0.0f), collinear ? 0.0f : float(j), 0});
        spec.uvs.insert(spec.uvs.end(), {0.5f * (q + i) * 0.999f + du * (q == 0 ? 1 : -1), float(j)});
      }
      spec.indices.insert(spec.indices.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
    }
    test::add_primitive(m, spec, material);
    const std::string path = dir + (side == 0 ? "/source.glb" : "/decoded.glb");
    ASSERT_EQ(write_gltf(m, path), "");
    ASSERT_TRUE(read_gltf(path, side == 0 ? source : decoded).ok);
  }
}

double psnr(const tinygltf::Model& source, const tinygltf::Model& decoded, SampleWeight weight) {
  SurfaceCompareOptions o;
  o.weight = weight;
  const SurfaceComparison c = compare_surface(source, decoded, o);
  EXPECT_TRUE(c.error.empty()) << c.error;
  EXPECT_EQ(c.primitives, 1u);
  return c.psnr;
}

TEST(SurfaceCompare, WeightingsAgreeWhereTheSourceDensityIsEven) {
  tinygltf::Model source, decoded;
  two_quads(1.0f, 1, source, decoded);
  const double texel = psnr(source, decoded, SampleWeight::source_texel);
  const double area = psnr(source, decoded, SampleWeight::surface_area);
  ASSERT_TRUE(std::isfinite(texel));
  EXPECT_NEAR(area, texel, 0.05);
}

// The narrow quad holds half the texels on a tenth of the surface: its error
// is half the texel mean and a tenth of the area mean (10 log10(5.5) =
// 7.4 dB apart), and the wide quad's the other way round (2.6 dB).
TEST(SurfaceCompare, AreaWeightingWeighsFacesByTheirSurface) {
  tinygltf::Model source, decoded;
  two_quads(0.1f, 1, source, decoded);
  double texel = psnr(source, decoded, SampleWeight::source_texel);
  double area = psnr(source, decoded, SampleWeight::surface_area);
  EXPECT_NEAR(area - texel, 10 * std::log10(0.5 / (0.1 / 1.1)), 0.3);

  two_quads(0.1f, 0, source, decoded);
  texel = psnr(source, decoded, SampleWeight::source_texel);
  area = psnr(source, decoded, SampleWeight::surface_area);
  EXPECT_NEAR(texel - area, 10 * std::log10((1 / 1.1) / 0.5), 0.3);
}

// Faces without area weigh nothing: a model of only such faces has no mean
// to give, and says so instead of dividing by zero.
TEST(SurfaceCompare, AreaWeightingOfFlatFacesIsAnError) {
  tinygltf::Model source, decoded;
  two_quads(1.0f, 1, source, decoded, true);
  SurfaceCompareOptions o;
  ASSERT_TRUE(compare_surface(source, decoded, o).error.empty());  // texels: a mean
  o.weight = SampleWeight::surface_area;
  const SurfaceComparison c = compare_surface(source, decoded, o);
  EXPECT_EQ(c.error, "the textured faces have no surface area to weigh");
}

}  // namespace
}  // namespace gltfwarp
