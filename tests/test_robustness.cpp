// Robustness on real-world and malicious input (issue 7), through the real
// CLI: valid-but-varied scenes round-trip validator-clean; malformed files
// fail with one line on stderr, a non-zero exit and no output; nothing ever
// crashes or hangs. The files are generated here (support/malformed.h).
// Encodes here pass --min-psnr 0 --always-implicit: these scenes test the
// container, and their small synthetic textures would otherwise fall back to
// explicit UVs, for quality or for size (those fallbacks have their own tests
// in test_roundtrip and test_warp_quality).
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "codec/encode/encode_report.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"
#include "support/corpus.h"
#include "support/malformed.h"

namespace fs = std::filesystem;
using namespace gltfwarp;
using namespace gltfwarp::test;

namespace {

std::string cli() { return GLTFWARP_CLI; }
bool fast() { return std::getenv("GLTFWARP_FAST_TESTS") != nullptr; }

std::string quote(const std::string& s) { return "'" + s + "'"; }

struct CliRun {
  int code = 0;
  std::string out, err;
};

// Runs the CLI under a timeout; stdout and stderr apart.
CliRun run_cli(const std::string& args, int timeout_s = 120) {
  static int counter = 0;
  const std::string err_file = scratch_dir("cli-stderr-" + std::to_string(counter++)) + "/err.txt";
  CliRun r;
  r.code = run_command(
      "timeout -k 5 " + std::to_string(timeout_s) + " " + cli() + " " + args + " 2>" + quote(err_file),
      &r.out);
  r.err = read_file(err_file);
  fs::remove_all(fs::path(err_file).parent_path());
  return r;
}

// The contract for a refusal: exit 1..127 (not a signal, not the timeout),
// one line on stderr starting with "gltf-warp: ".
void expect_clean(const CliRun& r, const std::string& what) {
  EXPECT_GE(r.code, 0) << what << " died of a signal: " << r.err;
  EXPECT_LT(r.code, 128) << what << " crashed: " << r.err;
  EXPECT_NE(r.code, 124) << what << " hung (timeout)";
  if (r.code == 0) return;
  ASSERT_FALSE(r.err.empty()) << what << " failed silently";
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << what << " error is not one line: " << r.err;
  EXPECT_EQ(r.err.rfind("gltf-warp: ", 0), 0u) << what << ": " << r.err;
}

std::set<std::string> error_codes(const ValidatorResult& r) {
  std::set<std::string> out;
  if (r.codes_json.empty()) return out;
  const auto codes = nlohmann::json::parse(r.codes_json, nullptr, false);
  if (codes.is_discarded() || !codes.is_object()) return out;
  for (auto it = codes.begin(); it != codes.end(); ++it) out.insert(it.key());
  return out;
}

// No validator error code in `path` that `source` does not have.
void expect_validator_clean_as(const std::string& path, const ValidatorResult& source) {
  if (!source.ran) return;
  const ValidatorResult r = validate(path);
  ASSERT_TRUE(r.ran) << r.raw;
  const auto before = error_codes(source), after = error_codes(r);
  for (const auto& c : after)
    EXPECT_TRUE(before.count(c)) << path << ": new validator error " << c << "\n" << r.raw;
}

// Rewrites a .gltf (with its .bin beside it) so that buffers and images are data URIs.
void embed_as_data_uris(const std::string& gltf_path) {
  auto doc = nlohmann::json::parse(read_file(gltf_path));
  const fs::path dir = fs::path(gltf_path).parent_path();
  const std::string bin_path = (dir / doc["buffers"][0]["uri"].get<std::string>()).string();
  const std::string bin = read_file(bin_path);
  for (auto& img : doc["images"]) {
    if (!img.contains("bufferView")) continue;
    const auto& v = doc["bufferViews"][img["bufferView"].get<int>()];
    const std::string bytes = bin.substr(v.value("byteOffset", size_t{0}), v["byteLength"].get<size_t>());
    img["uri"] = "data:" + img.value("mimeType", std::string("image/png")) + ";base64," + base64(bytes);
    img.erase("bufferView");
    img.erase("mimeType");
  }
  // The image views stay in the buffer, unreferenced: valid, and the codec drops them.
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  write_file(gltf_path, doc.dump());
  fs::remove(bin_path);
}

bool any_implicit(const tinygltf::Model& m) {
  for (const auto& mesh : m.meshes)
    for (const auto& p : mesh.primitives)
      if (p.extensions.count("GLTFWARP_implicit_texcoords")) return true;
  return false;
}

// A small plain textured scene and its encoded form, for the malformed files.
struct Pair {
  std::string plain, encoded;
};
Pair plain_and_encoded(const std::string& dir) {
  Pair p{dir + "/plain.glb", dir + "/encoded.glb"};
  tinygltf::Model m = empty_scene();
  add_primitive(m, grid_mesh(8, 6), add_material(m, add_texture(m, add_png_image(m, 64))));
  EXPECT_EQ(write_gltf(m, p.plain), "");
  const CliRun r =
      run_cli("encode -q --min-psnr 0 --always-implicit " + quote(p.plain) + " -o " + quote(p.encoded));
  EXPECT_EQ(r.code, 0) << r.err;
  return p;
}

}  // namespace

TEST(Robustness, VariedModelsRoundTrip) {
  const std::string dir = scratch_dir("robust-varied");
  for (auto& v : varied_models()) {
    SCOPED_TRACE(v.name);
    const std::string src = dir + "/" + v.name + v.container;
    tinygltf::Model copy = v.model;
    ASSERT_EQ(write_gltf(copy, src), "");
    if (v.name == "data-uris") embed_as_data_uris(src);
    const ValidatorResult source = validate(src);

    const std::string enc = dir + "/" + v.name + ".enc.glb", dec = dir + "/" + v.name + ".dec.glb";
    CliRun r = run_cli("encode --min-psnr 0 --always-implicit " + quote(src) + " -o " + quote(enc));
    expect_clean(r, "encode " + v.name);
    ASSERT_EQ(r.code, 0) << r.err << r.out;
    tinygltf::Model encoded;
    const auto rr = read_gltf(enc, encoded);
    ASSERT_TRUE(rr.ok) << rr.error;
    if (v.expect_implicit) {
      EXPECT_TRUE(any_implicit(encoded)) << r.out;
    }
    if (v.check_encoded) v.check_encoded(encoded, r.out + r.err);
    expect_validator_clean_as(enc, source);

    r = run_cli("decode " + quote(enc) + " -o " + quote(dec));
    expect_clean(r, "decode " + v.name);
    ASSERT_EQ(r.code, 0) << r.err;
    tinygltf::Model decoded;
    ASSERT_TRUE(read_gltf(dec, decoded).ok);
    EXPECT_FALSE(any_implicit(decoded));
    ASSERT_EQ(decoded.meshes.size(), v.model.meshes.size());
    for (size_t mi = 0; mi < decoded.meshes.size(); ++mi) {
      ASSERT_EQ(decoded.meshes[mi].primitives.size(), v.model.meshes[mi].primitives.size());
      for (size_t pi = 0; pi < decoded.meshes[mi].primitives.size(); ++pi) {
        const auto& before = v.model.meshes[mi].primitives[pi];
        const auto& after = decoded.meshes[mi].primitives[pi];
        for (const auto& [semantic, idx] : before.attributes)
          if (semantic != "TANGENT") {
            EXPECT_TRUE(after.attributes.count(semantic)) << semantic << " lost";
          }
        if (!is_triangle_mode(before.mode)) {
          EXPECT_EQ(after.mode, before.mode);
        }
      }
    }
    expect_validator_clean_as(dec, source);
    // Decoded output is a plain glTF: encoding it again works too.
    if (fast()) continue;
    r = run_cli("encode -q --min-psnr 0 --always-implicit " + quote(dec) + " -o " +
                quote(dir + "/" + v.name + ".again.glb"));
    expect_clean(r, "re-encode " + v.name);
    EXPECT_EQ(r.code, 0) << r.err;
  }
}

TEST(Robustness, DracoInputEncodesToo) {
  const std::string dir = scratch_dir("robust-draco-input");
  tinygltf::Model m = empty_scene();
  add_primitive(m, grid_mesh(8, 8), add_material(m, add_texture(m, add_png_image(m, 64))));
  ASSERT_EQ(write_gltf(m, dir + "/src.glb"), "");
  CliRun r =
      run_cli("encode -q --explicit-uvs " + quote(dir + "/src.glb") + " -o " + quote(dir + "/draco.glb"));
  ASSERT_EQ(r.code, 0) << r.err;
  tinygltf::Model draco;
  ASSERT_TRUE(read_gltf(dir + "/draco.glb", draco).ok);
  ASSERT_TRUE(draco.meshes[0].primitives[0].extensions.count(kDracoExtension));
  ASSERT_FALSE(any_implicit(draco));
  for (const std::string geometry : {"draco", "raw"}) {
    SCOPED_TRACE(geometry);
    const std::string out = dir + "/enc-" + geometry + ".glb";
    r = run_cli("encode -q --min-psnr 0 --always-implicit --geometry " + geometry + " " +
                quote(dir + "/draco.glb") + " -o " + quote(out));
    ASSERT_EQ(r.code, 0) << r.err;
    tinygltf::Model enc;
    ASSERT_TRUE(read_gltf(out, enc).ok);
    EXPECT_TRUE(any_implicit(enc));
    const bool uses_draco =
        std::count(enc.extensionsUsed.begin(), enc.extensionsUsed.end(), kDracoExtension) > 0;
    EXPECT_EQ(uses_draco, geometry == "draco") << "KHR_draco_mesh_compression declared only when used";
    expect_validator_clean_as(out, validate(dir + "/draco.glb"));
    r = run_cli("decode -q " + quote(out) + " -o " + quote(dir + "/dec-" + geometry + ".gltf"));
    EXPECT_EQ(r.code, 0) << r.err;
  }
}

TEST(Robustness, NormalizedIntegerUvsReadAsFloats) {
  for (auto& v : varied_models()) {
    if (v.name != "quantized-uv-short" && v.name != "normalized-uv-ushort" && v.name != "sparse") continue;
    SCOPED_TRACE(v.name);
    PrimitiveGeometry g;
    ASSERT_EQ(read_primitive(v.model, v.model.meshes[0].primitives[0], g), "");
    const VertexAttribute* uv = g.find("TEXCOORD_0");
    ASSERT_NE(uv, nullptr);
    const MeshSpec ref = grid_mesh(v.name == "sparse" ? 5 : 6, 5);
    ASSERT_EQ(uv->count(), ref.uvs.size() / 2);
    for (size_t e = 0; e < uv->count(); ++e)
      for (int i = 0; i < 2; ++i) EXPECT_NEAR(uv->get(e, i), ref.uvs[2 * e + i], 1.0 / 32767) << e;
  }
}

// UVs too far from 0 for a float to place a texel (a fuzzer's bit flip
// made one 3e32; the warp's lookups there read NaN): the primitive keeps its
// explicit UVs, untouched, and the report says why, even with
// --always-implicit; UVs within reach (a texture tiled 8 times) still go.
TEST(Robustness, UvsBeyondFloatReachKeepExplicitUvs) {
  const std::string dir = scratch_dir("robust-far-uvs");
  for (const float scale : {1e6f, 8.0f}) {
    SCOPED_TRACE(scale);
    tinygltf::Model m = empty_scene();
    MeshSpec mesh = grid_mesh(6, 5);
    for (float& v : mesh.uvs) v *= scale;
    add_primitive(m, mesh, add_material(m, add_texture(m, add_png_image(m, 32))));
    const std::string src = dir + "/src.glb", out = dir + "/out.glb";
    ASSERT_EQ(write_gltf(m, src), "");
    const CliRun r = run_cli("encode --min-psnr 0 --always-implicit " + quote(src) + " -o " + quote(out));
    ASSERT_EQ(r.code, 0) << r.err;
    tinygltf::Model enc;
    ASSERT_TRUE(read_gltf(out, enc).ok);
    if (scale > kMaxSourceUv) {
      EXPECT_FALSE(any_implicit(enc));
      EXPECT_NE(r.out.find("TEXCOORD_0 reaches 1e+06, beyond +-16384"), std::string::npos) << r.out;
      PrimitiveGeometry g;
      ASSERT_EQ(read_primitive(enc, enc.meshes[0].primitives[0], g), "");
      const VertexAttribute* uv = g.find("TEXCOORD_0");
      ASSERT_NE(uv, nullptr);
      float reach = 0;
      for (size_t e = 0; e < uv->count(); ++e) reach = std::max({reach, uv->get(e, 0), uv->get(e, 1)});
      EXPECT_NEAR(reach, 1e6f, 1e6f * 1e-3f);  // Draco's 12 bits over the range
    } else {
      EXPECT_TRUE(any_implicit(enc));
    }
  }
}

TEST(Robustness, MalformedFilesFailCleanly) {
  const std::string dir = scratch_dir("robust-malformed");
  const Pair pair = plain_and_encoded(dir);
  const auto files = malformed_files(dir, pair.plain, pair.encoded);
  ASSERT_GT(files.size(), 60u);
  for (const auto& f : files) {
    SCOPED_TRACE(f.name);
    const bool about_encoded = f.name.rfind("enc-", 0) == 0 || f.name.rfind("corrupt-", 0) == 0;
    const std::string out = dir + "/out.glb";
    for (const std::string verb : {"encode", "decode"}) {
      // Under the sanitizers (slow), only the verb each file is aimed at.
      if (fast() && (verb == "decode") != about_encoded && f.name.rfind("truncated", 0) != 0) continue;
      fs::remove(out);
      const CliRun r = run_cli(verb + " -q " + quote(f.path) + " -o " + quote(out), 60);
      expect_clean(r, verb + " " + f.name);
      if (r.code != 0) {
        EXPECT_FALSE(fs::exists(out)) << verb << " " << f.name << " left partial output";
      } else {
        tinygltf::Model back;
        const auto rr = read_gltf(out, back);
        EXPECT_TRUE(rr.ok) << verb << " " << f.name << " wrote an unreadable file: " << rr.error;
      }
      const bool must_fail = f.must_fail && (verb == "decode" ? about_encoded : !about_encoded);
      if (must_fail) {
        EXPECT_NE(r.code, 0) << verb << " accepted " << f.name;
      }
    }
    // info replays the UVs of an encoded file as decode does, so it reads what decode reads.
    if (!fast() || about_encoded) {
      const CliRun r = run_cli("info " + quote(f.path), 60);
      expect_clean(r, "info " + f.name);
      // Without a usable POSITION there is nothing to replay the UVs on.
      if (f.name == "enc-position-vec2.glb" || f.name == "enc-no-position.glb") {
        EXPECT_NE(r.code, 0) << "info accepted " << f.name;
      }
    }
  }
}

TEST(Robustness, ReaderRefusesBeforeAllocating) {
  // A 100-byte file declaring a 2^28-element MAT4 accessor (16 GiB) must be
  // refused by size, not by running out of memory.
  const std::string json =
      R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":96,"uri":"data:application/octet-stream;base64,)" +
      base64(std::string(96, '\0')) +
      R"("}],"bufferViews":[{"buffer":0,"byteLength":96}],"accessors":[{"bufferView":0,"componentType":5126,"type":"MAT4","count":268435456}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]})";
  tinygltf::Model m;
  const auto r = read_gltf_memory(reinterpret_cast<const uint8_t*>(json.data()), json.size(), m);
  ASSERT_TRUE(r.ok) << r.error;
  PrimitiveGeometry g;
  const std::string err = read_primitive(m, m.meshes[0].primitives[0], g);
  EXPECT_NE(err.find("past the end"), std::string::npos) << err;
  EXPECT_TRUE(g.attributes.empty());
  // External files are refused when not allowed (the fuzzers' mode).
  const std::string ext = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"x.bin"}]})";
  GltfReadOptions no_files;
  no_files.allow_external_files = false;
  EXPECT_FALSE(read_gltf_memory(reinterpret_cast<const uint8_t*>(ext.data()), ext.size(), m, no_files).ok);
}

// Flip and truncate bytes of an encoded file at a few hundred positions
// (spread over the whole file and concentrated on the JSON, the Draco data
// and the bitstream); `gltf-warp decode` must never crash or hang, and say
// why in one line when it fails.
TEST(Robustness, CorruptionSweep) {
  const std::string dir = scratch_dir("robust-sweep");
  const Pair pair = plain_and_encoded(dir);
  const std::string bytes = read_file(pair.encoded);
  Glb glb;
  ASSERT_TRUE(split_glb_file(bytes, glb));
  uint32_t json_len = 0;
  std::memcpy(&json_len, bytes.data() + 12, 4);
  const size_t json_start = 20;
  const size_t bin_start = 20 + json_len + 8;
  std::vector<std::pair<size_t, size_t>> regions;  // [start, length) in file bytes
  const auto& ext = glb.json["meshes"][0]["primitives"][0]["extensions"];
  for (const char* name : {"KHR_draco_mesh_compression", "GLTFWARP_implicit_texcoords"}) {
    ASSERT_TRUE(ext.contains(name));
    const auto& v = glb.json["bufferViews"][ext[name]["bufferView"].get<int>()];
    regions.push_back({bin_start + v.value("byteOffset", size_t{0}), v["byteLength"].get<size_t>()});
  }
  const int scale = fast() ? 1 : 3;
  std::mt19937 rng(7);
  struct Variant {
    std::string name, bytes;
  };
  std::vector<Variant> variants;
  auto flip = [&](size_t at, uint8_t mask) {
    std::string b = bytes;
    b[at] = static_cast<char>(b[at] ^ mask);
    variants.push_back({"flip-" + std::to_string(at) + "-" + std::to_string(mask), b});
  };
  for (int i = 0; i < 20 * scale; ++i)
    variants.push_back({"trunc-" + std::to_string(i), bytes.substr(0, rng() % bytes.size())});
  for (int i = 0; i < 15 * scale; ++i) flip(rng() % bytes.size(), static_cast<uint8_t>(1u << (rng() % 8)));
  for (const auto& [start, len] : regions)
    for (int i = 0; i < 25 * scale; ++i) flip(start + rng() % len, static_cast<uint8_t>(1 + rng() % 255));
  // JSON: change digits (offsets, counts, indices) rather than syntax.
  std::vector<size_t> digits;
  for (size_t i = json_start; i < json_start + json_len; ++i)
    if (bytes[i] >= '0' && bytes[i] <= '9') digits.push_back(i);
  for (int i = 0; i < 20 * scale && !digits.empty(); ++i) {
    std::string b = bytes;
    const size_t at = digits[rng() % digits.size()];
    b[at] = static_cast<char>('0' + rng() % 10);
    variants.push_back({"digit-" + std::to_string(at), b});
  }
  for (int i = 0; i < 5 * scale; ++i)
    flip(json_start + rng() % json_len, static_cast<uint8_t>(1 + rng() % 255));
  EXPECT_GE(variants.size(), fast() ? 100u : 300u);

  int failures = 0;
  for (size_t i = 0; i < variants.size(); ++i) {
    const std::string in = dir + "/v.glb", out = dir + "/v-out.glb";
    write_file(in, variants[i].bytes);
    fs::remove(out);
    const CliRun r = run_cli("decode -q " + quote(in) + " -o " + quote(out), 30);
    SCOPED_TRACE(variants[i].name);
    expect_clean(r, "decode " + variants[i].name);
    if (r.code != 0) {
      ++failures;
      EXPECT_FALSE(fs::exists(out)) << "partial output";
      if (r.code >= 128 || r.code < 0)
        write_file(dir + "/crash-" + variants[i].name + ".glb", variants[i].bytes);
    }
  }
  EXPECT_GT(failures, 0);
}
