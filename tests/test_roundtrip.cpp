// Round trips through the real CLI: every corpus model and generated samples
// are encoded and decoded; both files must pass the Khronos validator with no
// error code the source does not already have, and the scene must survive.
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <span>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "codec/encode/encoder.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/surface_compare.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_materials.h"
#include "format/gltf/gltf_primitive.h"
#include "support/corpus.h"
#include "support/malformed.h"
#include "tests/support/testing/sample_model.h"

namespace fs = std::filesystem;
using namespace gltfwarp;
using namespace gltfwarp::test;

namespace {

std::set<std::string> error_codes(const ValidatorResult& r) {
  std::set<std::string> out;
  if (r.codes_json.empty()) return out;
  const auto codes = nlohmann::json::parse(r.codes_json);
  for (auto it = codes.begin(); it != codes.end(); ++it) out.insert(it.key());
  return out;
}

struct Counts {
  size_t nodes, meshes, animations, skins, cameras, scenes;
  std::vector<std::vector<std::set<std::string>>> attributes;  // mesh -> prim -> semantics
  std::vector<std::vector<size_t>> triangles;
  double area = 0;
};

Counts counts_of(const std::string& path) {
  tinygltf::Model m;
  auto r = read_gltf(path, m);
  EXPECT_TRUE(r.ok) << r.error;
  Counts c{m.nodes.size(),
           m.meshes.size(),
           m.animations.size(),
           m.skins.size(),
           m.cameras.size(),
           m.scenes.size(),
           {},
           {}};
  for (const auto& mesh : m.meshes) {
    c.attributes.emplace_back();
    c.triangles.emplace_back();
    for (const auto& prim : mesh.primitives) {
      std::set<std::string> s;
      for (const auto& [k, v] : prim.attributes) s.insert(k);
      c.attributes.back().push_back(s);
      size_t tris = 0;
      if (is_triangle_mode(prim.mode)) {
        PrimitiveGeometry g;
        std::string err = read_primitive(m, prim, g);
        EXPECT_TRUE(err.empty()) << path << ": " << err;
        tris = g.triangles.size() / 3;
        if (const auto* pos = g.find("POSITION"))
          for (size_t f = 0; f < tris; ++f) {
            double p[3][3];
            for (int k = 0; k < 3; ++k)
              for (int i = 0; i < 3; ++i) p[k][i] = pos->get(g.triangles[3 * f + k], i);
            const double a[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
            const double b[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
            const double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                 a[0] * b[1] - a[1] * b[0]};
            c.area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
          }
      }
      c.triangles.back().push_back(tris);
    }
  }
  return c;
}

// The primitives (mesh, primitive) of each corpus model that carry the
// implicit map with the default options. A model that loses one of them to
// explicit UVs fails the round trip: without this, the encoder's fallback
// would let every size and quality check pass with the method switched off.
// A model may gain primitives (the test prints what it got).
const std::map<std::string, std::set<std::pair<int, int>>>& expected_implicit_primitives() {
  static const std::map<std::string, std::set<std::pair<int, int>>> expected = {
      // At the default aim (44 dB with PNG) the truck's sharp atlas outweighs
      // its source: explicit UVs. kTradedDown below checks its implicit map.
      {"CesiumMilkTruck", {}},
      {"Duck", {{0, 0}}},
      {"Duck-glb", {{0, 0}}},
      {"Fox", {{0, 0}}},
      {"MultiUVTest", {{0, 0}}},
      {"SphereWithCircleTexture", {{0, 0}}},
      {"TextureSettingsTest", {}},  // tiny quads with large images: explicit UVs are smaller
      {"TextureTransformTest", {{6, 0}, {7, 0}, {8, 0}}},
      // Explicit UVs with its PNGs written again losslessly (106,004 B at
      // 99 dB) are smaller than the map and a 62 dB atlas (105,209 B of
      // geometry and images against 104,477).
      {"TwoSidedPlane", {}},
      {"VertexColorTest", {}},  // 1-texel text cannot keep the quality floor
  };
  return expected;
}

std::set<std::pair<int, int>> implicit_primitives(const tinygltf::Model& m) {
  std::set<std::pair<int, int>> out;
  for (size_t i = 0; i < m.meshes.size(); ++i)
    for (size_t j = 0; j < m.meshes[i].primitives.size(); ++j)
      if (m.meshes[i].primitives[j].extensions.count(ext::kName)) out.insert({int(i), int(j)});
  return out;
}

// Models whose implicit map the round trip also checks with quality traded
// for bytes (--target-psnr 0), where the default keeps explicit UVs.
const std::map<std::string, std::set<std::pair<int, int>>> kTradedDown = {
    {"CesiumMilkTruck", {{0, 0}, {1, 0}}},
};

// encoded_bytes, if given, receives the encoded file's size.
// implicit_out, if given, receives the implicit-map primitives of the encoded file.
void check_round_trip(const std::string& name, const std::string& src, const std::string& extra_args = "",
                      uintmax_t* encoded_bytes = nullptr,
                      std::set<std::pair<int, int>>* implicit_out = nullptr) {
  const std::string dir = scratch_dir("roundtrip-" + name);
  const std::string enc = dir + "/enc.glb", dec = dir + "/dec.gltf";
  std::string out;
  ASSERT_EQ(run_command(
                std::string(GLTFWARP_CLI) + " encode -q " + extra_args + " '" + src + "' -o " + enc + " 2>&1",
                &out),
            0)
      << out;
  ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " decode -q " + enc + " -o " + dec + " 2>&1", &out), 0)
      << out;
  if (encoded_bytes) *encoded_bytes = fs::file_size(enc);

  const Counts a = counts_of(src), d = counts_of(dec);
  EXPECT_EQ(a.nodes, d.nodes);
  EXPECT_EQ(a.meshes, d.meshes);
  EXPECT_EQ(a.animations, d.animations);
  EXPECT_EQ(a.skins, d.skins);
  EXPECT_EQ(a.cameras, d.cameras);
  EXPECT_EQ(a.scenes, d.scenes);
  EXPECT_EQ(a.triangles, d.triangles);
  EXPECT_EQ(a.attributes, d.attributes);
  EXPECT_NEAR(a.area, d.area, 1e-3 * a.area + 1e-9) << "surface area changed beyond quantization";

  // The encoded file really uses our extension where textures sample TEXCOORD_0.
  tinygltf::Model em;
  ASSERT_TRUE(read_gltf(enc, em).ok);
  if (implicit_out) *implicit_out = implicit_primitives(em);
  const ValidatorResult vs = validate(src), ve = validate(enc), vd = validate(dec);
  if (!vs.ran) {
    if (on_ci()) FAIL() << "gltf-validator is not installed (run scripts/install-deps)";
    GTEST_SKIP() << "gltf-validator not installed";
  }
  const auto allowed = error_codes(vs);
  for (const auto& code : error_codes(ve))
    EXPECT_TRUE(allowed.count(code)) << "encoded file has new error " << code << ": " << ve.raw;
  for (const auto& code : error_codes(vd))
    EXPECT_TRUE(allowed.count(code)) << "decoded file has new error " << code << ": " << vd.raw;
  EXPECT_GE(ve.errors, 0) << ve.raw;
  EXPECT_GE(vd.errors, 0) << vd.raw;

  // The textured surface looks the same: issue 5's floor, 38 dB, sampled at
  // about one point per source texel of every face.
  tinygltf::Model sm, dm;
  ASSERT_TRUE(read_gltf(src, sm).ok);
  ASSERT_TRUE(read_gltf(dec, dm).ok);
  const SurfaceComparison q = compare_surface(sm, dm);
  if (q.error.empty()) {
    std::printf("%s: surface PSNR %.2f dB over %zu samples\n", name.c_str(), q.psnr, q.samples);
    EXPECT_GE(q.psnr, 38.0) << name;
  }
}

// Encodes the corpus model `name` in process; its report must hold exactly
// one atlas (the models these tests use have one textured material).
::testing::AssertionResult encode_corpus(const std::string& name, const EncodeOptions& options,
                                         EncodeReport& report) {
  const std::string path = corpus_path(name);
  if (path.empty()) return ::testing::AssertionFailure() << name << " is not in the corpus";
  tinygltf::Model model;
  if (!read_gltf(path, model).ok) return ::testing::AssertionFailure() << "cannot read " << path;
  const Error err = encode_model(model, options, report);
  if (err.failed()) return ::testing::AssertionFailure() << err.message;
  if (report.atlases.size() != 1) return ::testing::AssertionFailure() << report.atlases.size() << " atlases";
  return ::testing::AssertionSuccess();
}

}  // namespace

class CorpusRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST(CorpusPresence, CorpusIsFound) {
  GLTFWARP_REQUIRE_CORPUS();
  EXPECT_GE(corpus_models().size(), 9u);
}

// Every corpus model has its expectations (a new model must be added).
TEST(CorpusRoundTrip, EveryModelHasExpectations) {
  GLTFWARP_REQUIRE_CORPUS();
  for (const auto& m : corpus_models())
    EXPECT_TRUE(expected_implicit_primitives().count(m.name)) << "add " << m.name << " to the expectations";
}

// One test per corpus model (each within its own time limit, and run in
// parallel): the default round trip, the expected implicit primitives, and
// no file larger than explicit UVs.
class CorpusModelRoundTrip : public testing::TestWithParam<std::string> {};

TEST_P(CorpusModelRoundTrip, RoundTrips) {
  GLTFWARP_REQUIRE_CORPUS();
  std::string path;
  for (const auto& c : corpus_models())
    if (c.name == GetParam()) path = c.path;
  ASSERT_FALSE(path.empty()) << GetParam() << " is not in the corpus";
  const std::string& name = GetParam();
  uintmax_t ours = 0;
  std::set<std::pair<int, int>> got;
  check_round_trip(name, path, "", &ours, &got);
  std::printf("%s: %zu primitives with the implicit map\n", name.c_str(), got.size());
  for (const auto& [mesh, prim] : expected_implicit_primitives().at(name))
    EXPECT_TRUE(got.count({mesh, prim}))
        << name << " mesh " << mesh << " primitive " << prim << " no longer uses the implicit map";
  // The method exists to save bytes: the encoder keeps explicit UVs for any
  // atlas group that would cost more, so no file is larger than the same
  // model with explicit UVs (Draco-12) and its own images, beyond the
  // extension's few JSON bytes.
  const std::string dir = scratch_dir("explicit-" + name);
  std::string out;
  ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " encode -q --explicit-uvs '" + path + "' -o " + dir +
                            "/explicit.glb 2>&1",
                        &out),
            0)
      << out;
  const uintmax_t explicit_uvs = fs::file_size(dir + "/explicit.glb");
  std::printf("%s: %ju bytes, %ju with explicit UVs\n", name.c_str(), uintmax_t(ours),
              uintmax_t(explicit_uvs));
  EXPECT_LE(ours, explicit_uvs + explicit_uvs / 100 + 512) << name;
}

// The implicit map of the models that keep explicit UVs by default, with
// quality traded for bytes.
class CorpusTradedRoundTrip : public testing::TestWithParam<std::string> {};

TEST_P(CorpusTradedRoundTrip, KeepsTheImplicitMap) {
  GLTFWARP_REQUIRE_CORPUS();
  const auto traded = kTradedDown.find(GetParam());
  ASSERT_NE(traded, kTradedDown.end());
  std::string path;
  for (const auto& c : corpus_models())
    if (c.name == GetParam()) path = c.path;
  ASSERT_FALSE(path.empty()) << GetParam() << " is not in the corpus";
  std::set<std::pair<int, int>> got;
  check_round_trip(GetParam() + "-traded", path, "--target-psnr 0", nullptr, &got);
  for (const auto& [mesh, prim] : traded->second)
    EXPECT_TRUE(got.count({mesh, prim})) << GetParam() << " --target-psnr 0: mesh " << mesh << " primitive "
                                         << prim << " lost the implicit map";
}

std::vector<std::string> model_names(const std::map<std::string, std::set<std::pair<int, int>>>& models) {
  std::vector<std::string> names;
  for (const auto& [name, prims] : models) names.push_back(name);
  return names;
}

std::string test_id(const testing::TestParamInfo<std::string>& info) {
  std::string id = info.param;
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return id;
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusModelRoundTrip,
                         testing::ValuesIn(model_names(expected_implicit_primitives())), test_id);
INSTANTIATE_TEST_SUITE_P(Corpus, CorpusTradedRoundTrip, testing::ValuesIn(model_names(kTradedDown)), test_id);

TEST(CorpusRoundTrip, RawGeometryRoundTrips) {
  GLTFWARP_REQUIRE_CORPUS();
  for (const auto& m : corpus_models()) {
    if (m.name != "Duck" && m.name != "CesiumMilkTruck") continue;
    SCOPED_TRACE(m.name);
    check_round_trip(m.name + "-raw", m.path, "--geometry raw --target-psnr 0");
  }
}

TEST(GeneratedRoundTrip, SamplesRoundTrip) {
  for (const std::string shape : {"twisted-cone", "torus", "sphere", "plane"}) {
    SCOPED_TRACE(shape);
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model(shape, 3000, 256, model), "");
    const std::string src = scratch_dir("sample-" + shape) + "/src.glb";
    ASSERT_EQ(write_gltf(model, src), "");
    // The samples' textures have detail at every scale and no unused space,
    // so without --always-implicit the size rule would keep explicit UVs.
    // Not for the twisted cone: its tip squeezes a texture row into a point,
    // below the quality floor, so it shows the quality fallback instead.
    check_round_trip("sample-" + shape, src, shape == "twisted-cone" ? "" : "--always-implicit");
  }
}

TEST(GeneratedRoundTrip, EncodedFileUsesTheExtensionAndDropsExplicitUvs) {
  tinygltf::Model model;
  ASSERT_EQ(make_sample_model("twisted-cone", 2000, 128, model), "");
  const std::string dir = scratch_dir("uses-extension");
  ASSERT_EQ(write_gltf(model, dir + "/src.glb"), "");
  std::string out;
  ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " encode -q --min-psnr 0 --always-implicit " + dir +
                            "/src.glb -o " + dir + "/enc.glb 2>&1",
                        &out),
            0)
      << out;
  tinygltf::Model em;
  ASSERT_TRUE(read_gltf(dir + "/enc.glb", em).ok);
  const auto& prim = em.meshes[0].primitives[0];
  ASSERT_TRUE(prim.extensions.count(ext::kName));
  ASSERT_TRUE(prim.extensions.count(kDracoExtension));
  const auto& uv = em.accessors[prim.attributes.at("TEXCOORD_0")];
  EXPECT_EQ(uv.bufferView, -1) << "TEXCOORD_0 must be declared without data";
  EXPECT_NE(std::find(em.extensionsRequired.begin(), em.extensionsRequired.end(), ext::kName),
            em.extensionsRequired.end());
  // The Draco data must not carry TEXCOORD_0.
  const auto& dext = prim.extensions.at(kDracoExtension);
  EXPECT_FALSE(dext.Get("attributes").Has("TEXCOORD_0"));
}

// KHR_materials_variants: every material a primitive can show samples
// through the same TEXCOORD_0, so each variant's textures are warped into the
// primitive's atlas layout, and a viewer that switches variants shows each
// one's own colours. A primitive that keeps explicit UVs (here: points) and
// shows a variant material of an implicit one keeps the source textures.
TEST(GeneratedRoundTrip, MaterialVariantsShareTheAtlasLayout) {
  tinygltf::Model model;
  ASSERT_EQ(make_sample_model("sphere", 3000, 256, model), "");
  tinygltf::Texture tex = model.textures[model.materials[0].pbrMetallicRoughness.baseColorTexture.index];
  tex.source = add_gradient_png_image(model, 256);
  model.textures.push_back(tex);
  tinygltf::Material variant = model.materials[0];
  variant.name = "gradient";
  variant.pbrMetallicRoughness.baseColorTexture.index = static_cast<int>(model.textures.size() - 1);
  model.materials.push_back(variant);
  tinygltf::Value::Object mapping, root, named;
  mapping["material"] = tinygltf::Value(1);
  mapping["variants"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(0)});
  tinygltf::Value::Object prim_ext;
  prim_ext["mappings"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(mapping)});
  model.meshes[0].primitives[0].extensions["KHR_materials_variants"] = tinygltf::Value(prim_ext);
  named["name"] = tinygltf::Value(std::string("gradient"));
  root["variants"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(named)});
  model.extensions["KHR_materials_variants"] = tinygltf::Value(root);
  model.extensionsUsed.push_back("KHR_materials_variants");
  // The same vertices drawn as points, showing the variant material.
  tinygltf::Mesh points = model.meshes[0];
  points.primitives[0].extensions.clear();
  points.primitives[0].mode = TINYGLTF_MODE_POINTS;
  points.primitives[0].material = 1;
  model.meshes.push_back(points);
  tinygltf::Node node;
  node.mesh = 1;
  model.nodes.push_back(node);
  model.scenes[0].nodes.push_back(static_cast<int>(model.nodes.size() - 1));

  const std::string dir = scratch_dir("variants");
  const std::string src = dir + "/src.glb";
  ASSERT_EQ(write_gltf(model, src), "");
  const ValidatorResult vs = validate(src);
  if (!vs.ran && on_ci()) FAIL() << "gltf-validator is not installed (run scripts/install-deps)";
  EXPECT_EQ(vs.errors, 0) << vs.raw;
  tinygltf::Model sm;
  ASSERT_TRUE(read_gltf(src, sm).ok);
  auto base_image = [](const tinygltf::Model& m, int material) -> const std::vector<unsigned char>& {
    return m.images[m.textures[m.materials[material].pbrMetallicRoughness.baseColorTexture.index].source]
        .image;
  };
  // One page, then pages of 128 texels: the sphere is cut into primitives,
  // and every page's part gets copies of both materials.
  for (const std::string pages : {"", "--max-atlas-size 128"}) {
    SCOPED_TRACE(pages.empty() ? "one page" : pages);
    const std::string enc = dir + "/enc" + std::to_string(pages.size()) + ".glb";
    const std::string dec = dir + "/dec" + std::to_string(pages.size()) + ".glb";
    std::string out;
    ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " encode --always-implicit " + pages + " " + src +
                              " -o " + enc + " 2>&1",
                          &out),
              0)
        << out;
    EXPECT_EQ(out.find("explicit UVs kept"), std::string::npos) << out;
    ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " decode -q " + enc + " -o " + dec + " 2>&1", &out), 0)
        << out;
    tinygltf::Model em, dm;
    ASSERT_TRUE(read_gltf(enc, em).ok);
    ASSERT_TRUE(read_gltf(dec, dm).ok);
    const auto& parts = dm.meshes[0].primitives;
    EXPECT_EQ(parts.size() > 1, !pages.empty()) << out;
    for (size_t i = 0; i < parts.size(); ++i) {
      EXPECT_TRUE(em.meshes[0].primitives[i].extensions.count(ext::kName)) << "part " << i;
      const auto shown = primitive_materials(parts[i]);
      ASSERT_EQ(shown.size(), 2u);
      // Each material shows its own warped image.
      EXPECT_NE(base_image(dm, shown[0]), base_image(sm, 0));
      EXPECT_NE(base_image(dm, shown[1]), base_image(sm, 1));
      EXPECT_NE(base_image(dm, shown[0]), base_image(dm, shown[1]));
      EXPECT_NE(dm.meshes[1].primitives[0].material, shown[1]);
    }
    // The points keep the source's material and image.
    EXPECT_EQ(base_image(dm, dm.meshes[1].primitives[0].material), base_image(sm, 1));

    // What a viewer shows with each variant selected, against the source.
    // The floor holds for every source image, so for each variant; on pages
    // of 128 the density is held by --max-atlas-size (the report says
    // 0.6x), so there both variants together must keep it and each stays
    // near it. A wrong image would fall far below.
    const double each = pages.empty() ? 38.0 : 36.0;
    double squared = 0, samples = 0;
    for (int v = 0; v < 2; ++v) {
      tinygltf::Model a = sm, b = dm;
      a.meshes[0].primitives[0].material = v;
      for (auto& part : b.meshes[0].primitives) part.material = primitive_materials(part)[size_t(v)];
      a.meshes.resize(1);
      b.meshes.resize(1);
      const SurfaceComparison q = compare_surface(a, b);
      ASSERT_TRUE(q.error.empty()) << q.error;
      std::printf("%s variant %d: surface PSNR %.2f dB\n", pages.c_str(), v, q.psnr);
      EXPECT_GE(q.psnr, each) << "variant " << v;
      squared += double(q.samples) * 255.0 * 255.0 / std::pow(10.0, q.psnr / 10.0);
      samples += double(q.samples);
    }
    EXPECT_GE(10.0 * std::log10(samples * 255.0 * 255.0 / squared), 38.0) << "both variants together";
    if (!vs.ran) continue;
    const ValidatorResult ve = validate(enc), vd = validate(dec);
    EXPECT_EQ(ve.errors, 0) << ve.raw;
    EXPECT_EQ(vd.errors, 0) << vd.raw;
  }
}

// A JPEG source gets a JPEG atlas no larger than the image it replaces, at
// the quality floor: the Duck's PNG made JPEG (q85). With the flat mean fill
// beyond the gutters its atlas came out larger than the source (the steps
// at every patch outline cost JPEG coefficients); the pull-push fill
// (codec/encode/texture/atlas_fill.h) keeps the outlines smooth.
TEST(CorpusRoundTrip, JpegSourceAtlasIsNoLargerThanItsSource) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = corpus_path("Duck");
  ASSERT_FALSE(path.empty());
  tinygltf::Model model;
  ASSERT_TRUE(read_gltf(path, model).ok);
  ASSERT_EQ(model.images.size(), 1u);
  OIIO::ImageBuf pixels;
  std::string err;
  ASSERT_TRUE(decode_image(model.images[0].image, pixels, err)) << err;
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(encode_image(pixels, "image/jpeg", 85, jpeg, err)) << err;
  model.images[0].image.assign(jpeg.begin(), jpeg.end());
  model.images[0].mimeType = "image/jpeg";
  EncodeOptions o;
  // Measure the atlas itself: at equal quality the source re-encoded as a
  // lower-quality JPEG is smaller, so by default the Duck keeps explicit UVs
  // (FallbackComparesFilesAtEqualQuality checks that choice).
  o.quality_fallback = false;
  EncodeReport report;
  ASSERT_EQ(encode_model(model, o, report).message, "");
  ASSERT_EQ(report.atlases.size(), 1u);
  const auto& atlas = report.atlases[0];
  std::printf(
      "JPEG Duck: images %zu -> %zu bytes, %.2f dB; explicit UVs at equal quality %zu bytes (q%d), "
      "implicit %zu\n",
      atlas.source_image_bytes, atlas.atlas_image_bytes, atlas.psnr, atlas.explicit_bytes,
      atlas.explicit_image_quality, atlas.file_bytes);
  EXPECT_LE(atlas.atlas_image_bytes, atlas.source_image_bytes);
  EXPECT_GE(atlas.psnr, 38.0);
  bool jpeg_atlas = false;
  for (const auto& img : model.images)
    jpeg_atlas = jpeg_atlas || (img.name.find("atlas") != std::string::npos && img.mimeType == "image/jpeg");
  EXPECT_TRUE(jpeg_atlas) << "a JPEG source keeps JPEG";
}

// The first primitive's TEXCOORD_0 as the generated samples write it (tight
// floats), to edit in place; empty if it is stored otherwise.
std::span<float> first_primitive_uvs(tinygltf::Model& model) {
  const tinygltf::Accessor& acc = model.accessors[model.meshes[0].primitives[0].attributes.at("TEXCOORD_0")];
  const tinygltf::BufferView& view = model.bufferViews[acc.bufferView];
  if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || (view.byteStride != 0 && view.byteStride != 8))
    return {};
  auto* uv =
      reinterpret_cast<float*>(model.buffers[view.buffer].data.data() + view.byteOffset + acc.byteOffset);
  return {uv, 2 * acc.count};
}

// UVs squeezed by a KHR_texture_transform scale (what gltfpack writes: UVs
// quantized to [0, 1/16] with a 16x transform) sample the same texels per
// unit of surface, so the atlas keeps the same density. Before the
// transform's scale entered the density, such a Duck got a 16x thinner
// atlas (21.6 dB at twice the density) and fell back to explicit UVs.
TEST(GeneratedRoundTrip, TextureTransformScaleKeepsTheDensity) {
  EncodeReport plain_report, squeezed_report;
  for (const bool squeezed : {false, true}) {
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model("sphere", 3000, 256, model), "");
    if (squeezed) {
      const std::span<float> uv = first_primitive_uvs(model);
      ASSERT_FALSE(uv.empty());
      for (float& x : uv) x = (x - 0.25f) / 16.0f;  // back: 0.25 + 16 * uv
      tinygltf::Value::Object transform;
      transform["offset"] =
          tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(0.25), tinygltf::Value(0.25)});
      transform["scale"] =
          tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(16.0), tinygltf::Value(16.0)});
      model.materials[0].pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
          tinygltf::Value(transform);
      model.extensionsUsed.push_back("KHR_texture_transform");
    }
    EncodeOptions o;
    o.quality_fallback = false;  // the sample's busy texture would keep explicit UVs for size
    EncodeReport& report = squeezed ? squeezed_report : plain_report;
    ASSERT_EQ(encode_model(model, o, report).message, "");
    ASSERT_EQ(report.atlases.size(), 1u) << "squeezed " << squeezed;
    EXPECT_GE(report.atlases[0].psnr, 38.0) << "squeezed " << squeezed;
  }
  const auto& a = plain_report.atlases[0];
  const auto& b = squeezed_report.atlases[0];
  const double ratio = double(b.width) * b.height / (double(a.width) * a.height);
  std::printf("atlas %ux%u plain, %ux%u squeezed\n", a.width, a.height, b.width, b.height);
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 1.4);
}

// Issue 16, item 5: UVs that tile the texture (a cloth repeating its
// texture many times) would make an atlas of every repeat, many times the
// texels the source stores once. The encoder sees that from the UVs alone,
// before the costly steps, and keeps explicit UVs, saying why; the same
// model untiled is not caught by it.
TEST(GeneratedRoundTrip, TiledUvsKeepExplicitUvsBeforeTheWarp) {
  for (const float repeats : {1.0f, 24.0f}) {
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model("sphere", 3000, 256, model), "");
    const std::span<float> uv = first_primitive_uvs(model);
    ASSERT_FALSE(uv.empty());
    for (float& x : uv) x *= repeats;
    EncodeReport report;
    ASSERT_EQ(encode_model(model, EncodeOptions{}, report).message, "");
    ASSERT_EQ(report.primitives.size(), 1u);
    const PrimitiveReport& p = report.primitives[0];
    if (repeats > 1) {
      ASSERT_EQ(p.handling, Handling::fallback);
      EXPECT_EQ(p.fallback.reason, FallbackReason::texture_repeats);
      EXPECT_GT(p.fallback.texel_uses, 4.0 * p.fallback.image_texels);
      EXPECT_EQ(p.fallback.image_texels, 256.0 * 256.0);
      EXPECT_TRUE(report.atlases.empty()) << "no atlas was built";
    } else {
      EXPECT_NE(p.fallback.reason, FallbackReason::texture_repeats);
    }
  }
}

// A primitive whose atlas cannot reach the quality floor even at twice the
// density keeps explicit UVs (VertexColorTest's 1-texel text resampled at
// arbitrary sub-texel offsets: --resample-all, since by default its flat
// labels keep their source texels, test_texel_alignment.cpp);
// --always-implicit replaces it anyway.
TEST(CorpusRoundTrip, QualityFloorFallsBackToExplicitUvs) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = corpus_path("VertexColorTest");
  ASSERT_FALSE(path.empty());
  const std::string dir = scratch_dir("quality-floor");
  std::string out;
  for (const bool always : {false, true}) {
    const std::string enc = dir + (always ? "/always.glb" : "/floor.glb");
    ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " encode --resample-all " +
                              (always ? "--always-implicit " : "") + "'" + path + "' -o " + enc + " 2>&1",
                          &out),
              0)
        << out;
    EXPECT_EQ(out.find("fallback: explicit UVs kept") != std::string::npos, !always) << out;
    tinygltf::Model em;
    ASSERT_TRUE(read_gltf(enc, em).ok);
    const auto& prim = em.meshes[0].primitives[0];
    EXPECT_EQ(prim.extensions.count(ext::kName) == 1, always);
    const auto& dext = prim.extensions.at(kDracoExtension);
    EXPECT_EQ(dext.Get("attributes").Has("TEXCOORD_0"), !always) << "explicit UVs travel in the Draco data";
  }
}

// The report says why a primitive kept explicit UVs as data, not words:
// VertexColorTest's atlas resampled (--resample-all) stays below the quality
// floor, so its report carries that reason with the figures behind it, and
// its note the same.
TEST(CorpusRoundTrip, FallbackReportCarriesTypedReason) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = corpus_path("VertexColorTest");
  ASSERT_FALSE(path.empty());
  tinygltf::Model model;
  ASSERT_TRUE(read_gltf(path, model).ok);
  EncodeReport report;
  EncodeOptions o;
  o.align_texels = false;
  ASSERT_EQ(encode_model(model, o, report).message, "");
  size_t fallbacks = 0;
  for (const PrimitiveReport& p : report.primitives) {
    if (p.handling != Handling::fallback) continue;
    ++fallbacks;
    EXPECT_EQ(p.fallback.reason, FallbackReason::below_quality_floor);
    EXPECT_GT(p.fallback.min_psnr, 0.0);
    EXPECT_LT(p.fallback.psnr, p.fallback.min_psnr);
    EXPECT_GE(p.fallback.density_factor, 1.0);  // the boosts were tried
    size_t notes = 0;
    for (const Note& n : report.notes)
      if (n.about(p.mesh, p.primitive) && n.kind == NoteKind::fallback) {
        ++notes;
        EXPECT_EQ(n.fallback.reason, FallbackReason::below_quality_floor);
      }
    EXPECT_EQ(notes, 1u);
  }
  EXPECT_GT(fallbacks, 0u);
}

// Issue 5: a normal-mapped model lit before and after (warped: by default it
// keeps explicit UVs, which are smaller). The decoded file's
// tangents come from the new UVs and its normal map was re-expressed in
// them, so the lighting must match the source's (compare --lit: Lambert
// under three lights through each file's own NORMAL and TANGENT). Turning
// the decoded tangents around shows the measure sees a wrong frame.
TEST(CorpusRoundTrip, NormalMappedModelIsLitAlike) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = corpus_path("TwoSidedPlane");
  ASSERT_FALSE(path.empty());
  const std::string dir = scratch_dir("lit");
  std::string out;
  ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " encode -q --always-implicit '" + path + "' -o " + dir +
                            "/e.glb 2>&1",
                        &out),
            0)
      << out;
  ASSERT_EQ(
      run_command(std::string(GLTFWARP_CLI) + " decode -q " + dir + "/e.glb -o " + dir + "/d.glb 2>&1", &out),
      0)
      << out;
  tinygltf::Model sm, dm;
  ASSERT_TRUE(read_gltf(path, sm).ok);
  ASSERT_TRUE(read_gltf(dir + "/d.glb", dm).ok);
  SurfaceCompareOptions lit;
  lit.slot = "normalTexture";
  lit.lit = true;
  const SurfaceComparison q = compare_surface(sm, dm, lit);
  ASSERT_TRUE(q.error.empty()) << q.error;
  ASSERT_EQ(q.primitives, 1u);
  std::printf("TwoSidedPlane lit PSNR %.2f dB\n", q.psnr);
  // 36 dB before the warp took the source's own TANGENT as the old frame
  // (its handedness differs from the one MikkTSpace-with-flipped-v gives).
  EXPECT_GE(q.psnr, 45.0);

  // The decoded tangents turned by 90 degrees about the normal.
  auto& prim = dm.meshes[0].primitives[0];
  const tinygltf::Accessor& acc = dm.accessors[prim.attributes.at("TANGENT")];
  const tinygltf::BufferView& bv = dm.bufferViews[acc.bufferView];
  const size_t stride = bv.byteStride ? bv.byteStride : 16;
  auto* base = dm.buffers[bv.buffer].data.data() + bv.byteOffset + acc.byteOffset;
  for (size_t i = 0; i < acc.count; ++i) {
    float t[4];
    std::memcpy(t, base + i * stride, 16);
    const float turned[4] = {-t[2], t[1], t[0], t[3]};  // about +Y, the plane's normal
    std::memcpy(base + i * stride, turned, 16);
  }
  const SurfaceComparison wrong = compare_surface(sm, dm, lit);
  std::printf("with turned tangents %.2f dB\n", wrong.psnr);
  EXPECT_LT(wrong.psnr, q.psnr - 6.0);
}

// The quality floor's headroom is spent where the content is smooth: the
// Duck's flat body keeps the floor with half its texels, so its atlas is
// smaller with adaptive density than without, and still measures >= 38 dB.
TEST(CorpusRoundTrip, AdaptiveDensitySpendsHeadroomOnSmoothPatches) {
  GLTFWARP_REQUIRE_CORPUS();
  size_t bytes[2] = {0, 0};
  for (const bool adaptive : {false, true}) {
    EncodeOptions o;
    o.adaptive_density = adaptive;
    o.quality_fallback = false;  // at fixed density the Duck's atlas outweighs explicit UVs (size fallback)
    EncodeReport report;
    ASSERT_TRUE(encode_corpus("Duck", o, report));
    EXPECT_GE(report.atlases[0].psnr, 38.0);
    bytes[adaptive] = report.atlases[0].atlas_image_bytes;
  }
  std::printf("Duck atlas: %zu bytes fixed density, %zu adaptive\n", bytes[0], bytes[1]);
  EXPECT_LT(double(bytes[1]), 0.85 * double(bytes[0]));
}

// Where the Duck's colours agree across its UV seams, patches cross them and
// the seams fall (450 -> 431), while the floor still holds. (The Fox's one joined chart
// holds slits with marked steps, so it keeps its own charts either way:
// source_charts.h.)
TEST(CorpusRoundTrip, HiddenSourceSeamsAreCrossed) {
  GLTFWARP_REQUIRE_CORPUS();
  size_t seams[2] = {0, 0};
  for (const bool cross : {false, true}) {
    EncodeOptions o;
    o.cross_hidden_seams = cross;
    o.quality_fallback = false;
    EncodeReport report;
    ASSERT_TRUE(encode_corpus("Duck", o, report));
    EXPECT_GE(report.atlases[0].psnr, 38.0);
    for (const auto& pr : report.primitives) seams[cross] += pr.seam_edges;
  }
  std::printf("Duck seams: %zu inside every source chart, %zu crossing hidden seams\n", seams[0], seams[1]);
  EXPECT_LT(seams[1], seams[0]);
}

// The report's yardstick of our seams, the source's own UV charts (issue
// 19): the Fox's charts have seams, and every edge between the charts the
// partition keeps to is a seam of ours, so there are no more of them than
// our seams. Crossing the source's seams, nothing binds and the source's
// charts are the same.
TEST(CorpusRoundTrip, SourceChartsMeasureOurSeams) {
  GLTFWARP_REQUIRE_CORPUS();
  PrimitiveReport keep, cross;
  for (const bool crossing : {false, true}) {
    EncodeOptions o;
    o.keep_source_charts = !crossing;
    o.quality_fallback = false;
    EncodeReport report;
    ASSERT_TRUE(encode_corpus("Fox", o, report));
    ASSERT_EQ(report.primitives.size(), 1u);
    ASSERT_EQ(report.primitives[0].handling, Handling::implicit_uv);
    (crossing ? cross : keep) = report.primitives[0];
  }
  std::printf("Fox: source %u charts, %u seams, %.3f past tau; ours %zu seams (%u bound), crossing %zu\n",
              keep.source.charts, keep.source.seam_edges, keep.source.area_beyond_tau, keep.seam_edges,
              keep.source.bound_seam_edges, cross.seam_edges);
  EXPECT_GT(keep.source.charts, 1u);
  EXPECT_GT(keep.source.seam_edges, 0u);
  EXPECT_GT(keep.source.bound_seam_edges, 0u);
  EXPECT_LE(keep.source.bound_seam_edges, keep.seam_edges);
  EXPECT_GE(keep.source.area_beyond_tau, 0.0);
  EXPECT_LT(keep.source.area_beyond_tau, 1.0);
  EXPECT_LE(keep.source.non_disc_charts, keep.source.charts);
  EXPECT_GE(keep.source.non_disc_area, 0.0);
  EXPECT_LE(keep.source.non_disc_area, 1.0);
  EXPECT_EQ(cross.source.bound_seam_edges, 0u);
  EXPECT_EQ(cross.source.charts, keep.source.charts);
  EXPECT_EQ(cross.source.seam_edges, keep.source.seam_edges);
  EXPECT_EQ(cross.source.non_disc_charts, keep.source.non_disc_charts);
}

// Known answers on generated samples. The plane's UVs are one chart, a
// disc, without seams or stretch. The open cylinder's wrap round it (u from
// 0 to 1 on a repeating texture, with no seam left in it) into one chart
// that is a tube, no disc, which our patches must cut; its unit square
// spans a circumference of 2 pi and a height of 2, so every face is
// stretched about pi times across: all of the surface past tau.
TEST(GeneratedRoundTrip, SourceChartsOfAPlaneAndATube) {
  for (const std::string shape : {"plane", "cylinder"}) {
    SCOPED_TRACE(shape);
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model(shape, 2000, 128, model), "");
    EncodeOptions o;
    o.quality_fallback = false;
    EncodeReport report;
    ASSERT_FALSE(encode_model(model, o, report).failed());
    ASSERT_EQ(report.primitives.size(), 1u);
    const PrimitiveReport& p = report.primitives[0];
    ASSERT_EQ(p.handling, Handling::implicit_uv);
    const bool tube = shape == "cylinder";
    EXPECT_EQ(p.source.charts, 1u);
    EXPECT_EQ(p.source.seam_edges, 0u);
    EXPECT_EQ(p.source.bound_seam_edges, 0u);
    EXPECT_EQ(p.source.non_disc_charts, tube ? 1u : 0u);
    EXPECT_DOUBLE_EQ(p.source.non_disc_area, tube ? 1.0 : 0.0);
    EXPECT_DOUBLE_EQ(p.source.area_beyond_tau, tube ? 1.0 : 0.0);
    EXPECT_EQ(p.patches > 1, tube);
  }
}

// Issue 16, honest reports: with a lossy image coder the encoder prices the
// explicit-UV file at the atlas's own quality (the source re-encoded with the
// same coder, its JPEG quality searched), and keeps whichever is smaller.
// The alternative reaches the atlas's PSNR, and the choice follows the bytes.
TEST(CorpusRoundTrip, FallbackComparesFilesAtEqualQuality) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = corpus_path("Duck");
  ASSERT_FALSE(path.empty());
  for (const int q : {40, 90}) {
    tinygltf::Model model;
    ASSERT_TRUE(read_gltf(path, model).ok);
    EncodeOptions o;
    o.image_format = "jpeg";
    o.image_quality = q;
    o.quality_fallback = false;  // keep the atlas, to read its figures
    EncodeReport report;
    ASSERT_EQ(encode_model(model, o, report).message, "");
    ASSERT_EQ(report.atlases.size(), 1u);
    const AtlasReport& a = report.atlases[0];
    ASSERT_GT(a.explicit_bytes, 0u);
    ASSERT_GT(a.file_bytes, a.atlas_image_bytes);
    ASSERT_GT(a.explicit_image_quality, 0) << "a JPEG atlas is priced against JPEG sources";
    EXPECT_GE(a.explicit_psnr, a.psnr) << "the alternative is at least as good as the atlas";
    std::printf("Duck jpeg q%d: implicit %zu bytes at %.2f dB, explicit %zu at %.2f dB (q%d)\n", q,
                a.file_bytes, a.psnr, a.explicit_bytes, a.explicit_psnr, a.explicit_image_quality);
    // The same encode with the choice on keeps the smaller of the two.
    tinygltf::Model again;
    ASSERT_TRUE(read_gltf(path, again).ok);
    o.quality_fallback = true;
    EncodeReport chosen;
    ASSERT_EQ(encode_model(again, o, chosen).message, "");
    bool fell_back = false;
    uint32_t kept = 0;
    for (const PrimitiveReport& p : chosen.primitives)
      if (p.handling == Handling::fallback) {
        fell_back = true;
        kept = p.fallback.images_kept;  // the Duck: one primitive
        EXPECT_EQ(p.fallback.reason, FallbackReason::explicit_smaller);
        EXPECT_GT(p.fallback.implicit_bytes, p.fallback.explicit_bytes);
      }
    EXPECT_EQ(fell_back, a.file_bytes > a.explicit_bytes) << "q" << q;
    if (fell_back) {  // asked for JPEG, the images are JPEG with explicit UVs too, unless it would not shrink
                      // them
      uint32_t png = 0;
      for (const tinygltf::Image& img : again.images) {
        EXPECT_TRUE(img.mimeType == "image/jpeg" || img.mimeType == "image/png") << img.mimeType;
        png += img.mimeType == "image/png";
      }
      EXPECT_EQ(png, kept) << "q" << q;
    }
  }
}

// The quality floor is checked on the texels the file holds: a JPEG atlas
// is measured after coding, so the encoder's PSNR is the one a viewer
// sees (it read 41.8 dB for a Duck whose JPEG atlas showed 35.8).
TEST(CorpusRoundTrip, ReportedQualityIsThatOfTheCodedImages) {
  GLTFWARP_REQUIRE_CORPUS();
  const std::string path = corpus_path("Duck");
  ASSERT_FALSE(path.empty());
  const std::string dir = scratch_dir("jpeg-quality");
  std::string out, ignored;
  ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) +
                            " encode --image-format jpeg --jpeg-quality 60 --always-implicit '" + path +
                            "' -o " + dir + "/e.glb 2>&1",
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(std::string(GLTFWARP_CLI) + " decode -q " + dir + "/e.glb -o " + dir + "/d.glb 2>&1",
                        &ignored),
            0)
      << ignored;
  const size_t at = out.find("surface PSNR ");
  ASSERT_NE(at, std::string::npos) << out;
  const double reported = std::atof(out.c_str() + at + 13);
  tinygltf::Model sm, dm;
  ASSERT_TRUE(read_gltf(path, sm).ok);
  ASSERT_TRUE(read_gltf(dir + "/d.glb", dm).ok);
  const SurfaceComparison q = compare_surface(sm, dm);
  ASSERT_TRUE(q.error.empty()) << q.error;
  std::printf("Duck as JPEG q60: encoder %.2f dB, decoded file %.2f dB\n", reported, q.psnr);
  EXPECT_NEAR(reported, q.psnr, 0.25);
  EXPECT_GE(q.psnr, 38.0) << "the floor holds on the coded images";
}

// The Fox's flat-coloured atlas is already smaller than its source at its
// measured density (39.6 dB): a 40 dB goal raises it there and keeps it
// there, while without the goal the adaptive density trades it down towards
// the 38 dB floor.
TEST(CorpusRoundTrip, QualityGoalHoldsWhileImagesBeatTheirSources) {
  GLTFWARP_REQUIRE_CORPUS();
  struct Run {
    double psnr = 0;
    size_t bytes = 0, source = 0;
  };
  auto run = [&](bool adaptive, double goal) {
    EncodeOptions o;
    o.adaptive_density = adaptive;
    o.goal_psnr = goal;
    o.quality_fallback = false;
    EncodeReport report;
    Run r;
    EXPECT_TRUE(encode_corpus("Fox", o, report));
    if (report.atlases.size() != 1) return r;
    r.psnr = report.atlases[0].psnr;
    r.bytes = report.atlases[0].atlas_image_bytes;
    r.source = report.atlases[0].source_image_bytes;
    return r;
  };
  // fixed: the measured density as it is (goal 0: no boost); goal 40: raised
  // to reach it, then halved no lower; 0: traded down to the floor.
  const Run fixed = run(false, 0), goal = run(true, 40), floor = run(true, 0);
  std::printf("Fox atlas: fixed %zu B %.2f dB, goal 40 %zu B %.2f dB, no goal %zu B %.2f dB (source %zu B)\n",
              fixed.bytes, fixed.psnr, goal.bytes, goal.psnr, floor.bytes, floor.psnr, fixed.source);
  ASSERT_GT(fixed.bytes, 0u);
  ASSERT_LE(fixed.bytes, fixed.source) << "precondition: the fixed-density atlas beats its source";
  EXPECT_GE(goal.psnr, std::min(40.0, fixed.psnr) - 0.05);
  EXPECT_LE(goal.bytes, fixed.source);
  EXPECT_GE(floor.psnr, 38.0);
  EXPECT_LT(floor.psnr, goal.psnr) << "without the goal, quality is traded for bytes";
  EXPECT_LE(floor.bytes, goal.bytes);
}
