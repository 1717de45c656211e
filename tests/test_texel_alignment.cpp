// Texel-exact patches (codec/encode/atlas/texel_alignment.h): where a
// patch's source map is a similarity, its placement puts every source texel
// centre on an atlas texel centre, so the warp copies texels instead of
// resampling them. Checked on the placement arithmetic the decoder runs, and
// end to end on a generated flat model whose UVs are a turned, scaled copy
// of its positions over a sharp checker texture.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <vector>

#include "codec/encode/atlas/texel_alignment.h"
#include "codec/encode/encoder.h"
#include "format/bitstream/decode_uvs.h"
#include "format/gltf/gltf_io.h"
#include "support/corpus.h"
#include "support/malformed.h"

namespace gltfwarp {
namespace {

// Distance from v to the nearest whole number.
double off_whole(double v) { return std::abs(v - std::round(v)); }

// A patch of 6 random triangles whose source texels are a random
// similarity of their layout (mirrored when asked), on a 1024 x 512 image.
struct RandomPatch {
  bool mirror = false;
  double angle = 0, density = 0, tx = 0, ty = 0;
  uint32_t width = 1024, height = 512;
  std::vector<double> xy;
  std::vector<float> uv;
  std::vector<uint32_t> faces;
  SimilarityFit fit;  // fit_texel_alignment of the above
  UvMap map;          // 4096 x 4096, at 0.5 to 1.5 of the source's density
  // The source texel position of a layout point.
  void source_of(double px, double py, double& sx, double& sy) const {
    const double my = mirror ? -py : py;
    sx = density * (std::cos(angle) * px - std::sin(angle) * my) + tx;
    sy = density * (std::sin(angle) * px + std::cos(angle) * my) + ty;
  }
};

RandomPatch random_patch(std::mt19937& rng, bool mirror) {
  std::uniform_real_distribution<double> uni(0, 1);
  RandomPatch p;
  p.mirror = mirror;
  p.angle = 6.2831853 * uni(rng), p.density = 50 + 400 * uni(rng);
  p.tx = 1000 * uni(rng), p.ty = 1000 * uni(rng);
  for (uint32_t f = 0; f < 6; ++f) {
    p.faces.push_back(f);
    for (int v = 0; v < 3; ++v) {
      const double px = uni(rng), py = uni(rng);
      double sx, sy;
      p.source_of(px, py, sx, sy);
      p.xy.push_back(px), p.xy.push_back(py);
      p.uv.push_back(float(sx / p.width)), p.uv.push_back(float(sy / p.height));
    }
  }
  p.fit = fit_texel_alignment(p.xy, p.uv, p.faces, p.width, p.height, 0.02);
  p.map.texel_scale = float(p.density * (0.5 + uni(rng)));
  p.map.atlas_width = p.map.atlas_height = 4096;
  return p;
}

// The placement the packer writes for an aligned transform, at whole
// position (0, 0) (a fraction of 1 carries into the whole part).
PatchPlacement placement_of(const AlignedTransform& at) {
  PatchPlacement pl;
  pl.scale_step = at.scale_step;
  if (at.coarse) {
    pl.rotation = at.rotation;
  } else {
    pl.fine = true;
    pl.cos_q = at.cos_q, pl.sin_q = at.sin_q;
    pl.x_frac = uint32_t(std::lround(at.frac_x * kFineFracSteps)) % kFineFracSteps;
    pl.y_frac = uint32_t(std::lround(at.frac_y * kFineFracSteps)) % kFineFracSteps;
    pl.x = at.frac_x >= 1 ? 1 : 0, pl.y = at.frac_y >= 1 ? 1 : 0;
  }
  return pl;
}

TEST(TexelAlignment, PlacementPutsSourceTexelCentresOnAtlasTexelCentres) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    // A patch of random points, its source texels a random similarity of
    // them (mirrored every other trial).
    const bool mirror = trial % 2 == 1;
    const RandomPatch patch = random_patch(rng, mirror);
    const std::vector<double>& xy = patch.xy;
    const std::vector<float>& uv = patch.uv;
    const uint32_t W = patch.width, H = patch.height;
    const double density = patch.density;
    const SimilarityFit& fit = patch.fit;
    const UvMap& map = patch.map;
    ASSERT_TRUE(fit.ok) << "trial " << trial;
    EXPECT_EQ(fit.mirror, mirror);
    for (int turn = 0; turn < 4; ++turn) {
      AlignedTransform at;
      ASSERT_TRUE(aligned_transform(fit, turn, double(map.texel_scale), 1.5, at));
      PatchPlacement pl = placement_of(at);
      pl.x += 1000, pl.y += 1000;
      // Same density as the source, and each corner's atlas texel position
      // minus its source texel position (turned) a whole vector: centres
      // land on centres.
      EXPECT_NEAR(placement_scale(map, pl), density, density * 1e-4);
      for (size_t c = 0; c < xy.size() / 2; ++c) {
        double ax, ay;
        placement_texel(map, pl, xy[2 * c], xy[2 * c + 1], ax, ay);
        double sx = double(uv[2 * c]) * W, sy = double(uv[2 * c + 1]) * H;
        if (mirror) sy = -sy;  // the placement lands on the source reflected across its rows
        for (int k = 0; k < turn; ++k) std::swap(sx, sy), sx = -sx;
        EXPECT_LT(off_whole(ax - sx), 0.02) << "trial " << trial << " turn " << turn << " corner " << c;
        EXPECT_LT(off_whole(ay - sy), 0.02) << "trial " << trial << " turn " << turn << " corner " << c;
      }
    }
  }
}

// A viewer's MIP level k averages blocks of 2^k x 2^k texels. The whole
// position that mip_block_residue asks for puts every 4 x 4 block of the
// source's texels on one 4 x 4 block of the atlas's, so levels 1 and 2
// hold the source's own averages too.
TEST(TexelAlignment, BlockResidueLinesUpMipBlocks) {
  std::mt19937 rng(11);
  constexpr int kBlock = 4;
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const RandomPatch patch = random_patch(rng, trial % 2 == 1);
    const std::vector<double>& xy = patch.xy;
    const double density = patch.density;
    const SimilarityFit& fit = patch.fit;
    const UvMap& map = patch.map;
    ASSERT_TRUE(fit.ok);
    for (int turn = 0; turn < 4; ++turn) {
      AlignedTransform at;
      ASSERT_TRUE(aligned_transform(fit, turn, double(map.texel_scale), 1.5, at));
      // The mask frame the packer builds (build_mask), then a whole position near 1000 with the residue.
      const double unit = double(map.texel_scale) * patch_scale(at.scale_step);
      double sc, ss, ox = 0, oy = 0;
      PatchPlacement pl = placement_of(at);
      if (at.coarse) {
        rotation_cos_sin(at.rotation, sc, ss);
        sc *= unit, ss *= unit;
      } else {
        sc = unit * at.cos_q * 0x1p-15, ss = unit * at.sin_q * 0x1p-15;
        ox = at.frac_x, oy = at.frac_y;
      }
      const BlockResidue res = mip_block_residue(fit, sc, ss, ox, oy, kBlock);
      pl.x += 1000 + ((res.x - 1000) % kBlock + kBlock) % kBlock;
      pl.y += 1000 + ((res.y - 1000) % kBlock + kBlock) % kBlock;
      // The source texel each atlas texel centre holds, by the decoder's
      // arithmetic: over a 12 x 12 square of atlas texels, every atlas
      // block holds one source block.
      const double c = 1.0 / density;  // layout units per texel
      double ax0, ay0;
      placement_texel(map, pl, xy[0], xy[1], ax0, ay0);
      std::map<std::pair<long, long>, std::pair<long, long>> block_of;  // source block -> atlas block
      for (int dy = -6; dy < 6; ++dy)
        for (int dx = -6; dx < 6; ++dx) {
          // The atlas texel centre (jx, jy), back to the layout by the placement's inverse (a similarity).
          const double jx = std::floor(ax0) + dx + 0.5, jy = std::floor(ay0) + dy + 0.5;
          double ex, ey, fx, fy;
          placement_texel(map, pl, xy[0] + c, xy[1], ex, ey);
          placement_texel(map, pl, xy[0], xy[1] + c, fx, fy);
          const double det = (ex - ax0) * (fy - ay0) - (fx - ax0) * (ey - ay0);
          const double u = ((jx - ax0) * (fy - ay0) - (fx - ax0) * (jy - ay0)) / det;
          const double v = ((ex - ax0) * (jy - ay0) - (jx - ax0) * (ey - ay0)) / det;
          double sx, sy;
          patch.source_of(xy[0] + u * c, xy[1] + v * c, sx, sy);
          ASSERT_LT(off_whole(sx - 0.5), 0.02);
          ASSERT_LT(off_whole(sy - 0.5), 0.02);
          const std::pair<long, long> sb{long(std::floor(std::floor(sx) / kBlock)),
                                         long(std::floor(std::floor(sy) / kBlock))};
          const std::pair<long, long> ab{long(std::floor(std::floor(jx) / kBlock)),
                                         long(std::floor(std::floor(jy) / kBlock))};
          const auto [it, fresh] = block_of.emplace(sb, ab);
          EXPECT_EQ(it->second, ab) << "trial " << trial << " turn " << turn;
          ++checked;
        }
    }
  }
  EXPECT_EQ(checked, 40 * 4 * 144);
}

TEST(TexelAlignment, StretchedSourceIsNotAligned) {
  const std::vector<double> xy = {0, 0, 1, 0, 0, 1, 1, 0, 1, 1, 0, 1};
  std::vector<float> uv;
  for (size_t i = 0; i < xy.size(); i += 2)
    uv.push_back(float(0.1 + 0.5 * xy[i])), uv.push_back(float(0.1 + 0.25 * xy[i + 1]));
  const std::vector<uint32_t> faces = {0, 1};
  EXPECT_FALSE(fit_texel_alignment(xy, uv, faces, 256, 256, 0.02).ok);  // 128 x 64 texels for a square
  EXPECT_TRUE(fit_texel_alignment(xy, uv, faces, 256, 512, 0.02).ok);   // 128 x 128
  EXPECT_FALSE(fit_texel_alignment(xy, uv, faces, 256, 514, 0.02).ok);  // 128 x 128.5
}

// A flat grid whose UVs are its positions turned by 30 degrees and scaled
// into the middle of a 256 x 256 checker of 4-texel squares: any
// resampling smears the squares' edges.
tinygltf::Model turned_label() {
  test::MeshSpec grid = test::grid_mesh(6, 4);
  for (size_t v = 0; v < grid.positions.size() / 3; ++v) {
    grid.positions[3 * v + 2] = 0;
    const double x = grid.positions[3 * v] - 0.5, y = grid.positions[3 * v + 1] - 0.5;
    const double c = std::cos(0.5235988), s = std::sin(0.5235988);
    grid.uvs[2 * v] = float(0.5 + 0.6 * (c * x - s * y));
    grid.uvs[2 * v + 1] = float(0.5 + 0.6 * (s * x + c * y));
  }
  tinygltf::Model m = test::empty_scene();
  test::add_primitive(m, grid, test::add_material(m, test::add_texture(m, test::add_png_image(m, 256))));
  return m;
}

TEST(TexelAlignment, FlatModelKeepsItsSourceTexels) {
  double psnr[2] = {0, 0};
  uint32_t aligned[2] = {0, 0};
  for (int align = 0; align < 2; ++align) {
    tinygltf::Model m = turned_label();
    EncodeOptions o;
    o.align_texels = align == 1;
    o.quality_fallback = false;
    EncodeReport r;
    ASSERT_EQ(encode_model(m, o, r).message, "");
    ASSERT_EQ(r.atlases.size(), 1u);
    psnr[align] = r.atlases[0].psnr;
    aligned[align] = r.atlases[0].aligned_patches;
    EXPECT_EQ(r.atlases[0].overlapping_texels, 0u);
  }
  std::printf("turned label: %.1f dB resampled, %.1f dB texel-exact (%u patches)\n", psnr[0], psnr[1],
              aligned[1]);
  EXPECT_EQ(aligned[0], 0u);
  EXPECT_GE(aligned[1], 1u);
  // Copies, not resamplings: only the patch outline (the gutter beyond it)
  // differs from what the source shows.
  EXPECT_GE(psnr[1], 50.0);
  EXPECT_GE(psnr[1], psnr[0] + 6.0);
}

// VertexColorTest's labels and check marks are flat quads over 256^2 PNGs of
// 1-texel text. Resampled, no density reaches the quality floor and both
// primitives keep explicit UVs; texel-exact, each keeps its source texels,
// and the file is smaller than the explicit-UV one at the floor.
TEST(TexelAlignment, VertexColorTestLabelsKeepTheirTexels) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = test::corpus_path("VertexColorTest");
  ASSERT_FALSE(path.empty()) << "VertexColorTest is not in the corpus";
  size_t bytes[2] = {0, 0};
  for (int align = 0; align < 2; ++align) {
    tinygltf::Model model;
    ASSERT_TRUE(read_gltf(path, model).ok);
    EncodeOptions o;
    o.align_texels = align == 1;
    EncodeReport r;
    ASSERT_EQ(encode_model(model, o, r).message, "");
    size_t implicit = 0;
    for (const PrimitiveReport& p : r.primitives) implicit += p.handling == Handling::implicit_uv;
    if (align == 0) {
      EXPECT_EQ(implicit, 0u) << "resampled, every primitive falls back";
    } else {
      EXPECT_EQ(implicit, 2u);
      for (const AtlasReport& a : r.atlases) {
        EXPECT_GE(a.aligned_patches, 1u);
        EXPECT_GE(a.psnr, 55.0);
        EXPECT_EQ(a.overlapping_texels, 0u);
        // MIP blocks lined up with the source's (mip_block_residue): level
        // 1 holds the source's own averages, as good as level 0 (it was
        // 24 dB against 66 dB with the blocks shifted).
        EXPECT_GE(a.mip_psnr[1], a.mip_psnr[0] - 1.0);
        // Lined up to 16-texel blocks in sides that are multiples of 16,
        // level 3 keeps the text readable: 41.9 and 30.5 dB (22.7 and
        // 23.7 dB with 4-texel blocks in sides that are multiples of 4).
        EXPECT_GE(a.mip_psnr[3], 28.0);
      }
    }
    const std::string out = test::scratch_dir("texel-exact") + (align ? "/exact.glb" : "/resampled.glb");
    ASSERT_EQ(write_gltf(model, out), "");
    bytes[align] = std::filesystem::file_size(out);
  }
  std::printf("VertexColorTest: %zu bytes texel-exact, %zu resampled (explicit UVs)\n", bytes[1], bytes[0]);
  EXPECT_LT(bytes[1], bytes[0]);
}

}  // namespace
}  // namespace gltfwarp
