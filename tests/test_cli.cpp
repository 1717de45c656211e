// The CLI as a user meets it: --help on every verb, one-line errors with a
// non-zero exit on bad input, and no partial output files.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "support/corpus.h"

using namespace gltfwarp::test;
namespace fs = std::filesystem;

namespace {
std::string cli() { return GLTFWARP_CLI; }

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expect_one_line_failure(const std::string& args, const std::string& must_contain = "") {
  std::string out;
  const int code = run_command(cli() + " " + args + " 2>&1 >/dev/null", &out);
  EXPECT_NE(code, 0) << args;
  EXPECT_LT(code, 128) << "crashed: " << args;
  ASSERT_FALSE(out.empty()) << args;
  EXPECT_EQ(out.find('\n'), out.size() - 1) << "not one line: " << out;
  EXPECT_EQ(out.rfind("gltf-warp: ", 0), 0u) << out;
  if (!must_contain.empty()) {
    EXPECT_NE(out.find(must_contain), std::string::npos) << out;
  }
}
}  // namespace

TEST(Cli, EveryVerbHasHelp) {
  for (const std::string verb : {"encode", "decode", "info", "sample"}) {
    std::string out;
    EXPECT_EQ(run_command(cli() + " " + verb + " --help", &out), 0) << verb;
    EXPECT_NE(out.find("Usage"), std::string::npos) << verb;
  }
}

TEST(Cli, BadInputGivesOneLineErrorAndNoOutput) {
  const std::string dir = scratch_dir("cli-bad");
  std::ofstream(dir + "/broken.gltf") << "{\"asset\": {\"version\": \"2.0\"";
  std::ofstream(dir + "/empty.glb") << "";
  std::ofstream(dir + "/garbage.glb") << "glTF this is not a binary glTF at all";
  for (const std::string f : {"broken.gltf", "empty.glb", "garbage.glb"}) {
    expect_one_line_failure("encode " + dir + "/" + f + " -o " + dir + "/out.glb");
    expect_one_line_failure("decode " + dir + "/" + f + " -o " + dir + "/out.glb");
    expect_one_line_failure("info " + dir + "/" + f);
    EXPECT_FALSE(fs::exists(dir + "/out.glb"));
  }
  expect_one_line_failure("compare --weight volume " + dir + "/broken.gltf " + dir + "/broken.gltf",
                          "--weight");
  expect_one_line_failure("encode --quality-weight volume " + dir + "/broken.gltf -o " + dir + "/x.glb",
                          "--quality-weight");
  expect_one_line_failure("encode " + dir + "/missing.glb -o " + dir + "/out.glb");
  expect_one_line_failure("encode");
  expect_one_line_failure("frobnicate");
  expect_one_line_failure("encode " + dir + "/broken.gltf -o " + dir + "/out.glb --max-distortion 0.5");
  expect_one_line_failure("encode " + dir + "/broken.gltf -o " + dir +
                          "/out.glb --quality high --target-psnr 40");
  expect_one_line_failure("encode " + dir + "/broken.gltf -o " + dir + "/out.glb --quality best");
}

TEST(Cli, SampleEncodeDecodeInfo) {
  const std::string dir = scratch_dir("cli-ok");
  std::string out;
  // A torus: its source texel density is even, so a 128² texture keeps 38 dB
  // (the twisted cone's tip squeezes a full texture row into a point).
  ASSERT_EQ(
      run_command(cli() + " sample --shape torus --faces 1500 --texture-size 128 -o " + dir + "/s.glb 2>&1",
                  &out),
      0)
      << out;
  // --always-implicit: the sample's texture has detail at every scale and no
  // unused space, so explicit UVs are smaller and the encoder would keep them.
  ASSERT_EQ(run_command(cli() + " encode --always-implicit --report-greedy " + dir + "/s.glb -o " + dir +
                            "/e.glb 2>&1",
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("implicit-uv"), std::string::npos) << out;
  EXPECT_NE(out.find("greedy baseline"), std::string::npos) << out;
  EXPECT_NE(out.find("holes"), std::string::npos) << out;
  ASSERT_EQ(run_command(cli() + " info --json " + dir + "/e.glb 2>&1", &out), 0) << out;
  EXPECT_NE(out.find("\"bitstream_bytes\""), std::string::npos) << out;
  ASSERT_EQ(run_command(cli() + " decode " + dir + "/e.glb -o " + dir + "/d.gltf 2>&1", &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir + "/d.bin"));
  // The round trip compared both ways (per texel, by area): each a PSNR.
  for (const std::string weight : {"texel", "area"}) {
    ASSERT_EQ(run_command(
                  cli() + " compare --weight " + weight + " " + dir + "/s.glb " + dir + "/d.gltf 2>&1", &out),
              0)
        << out;
    double db = 0;
    ASSERT_EQ(std::sscanf(out.c_str(), "surface PSNR %lf dB", &db), 1) << out;
    EXPECT_GT(db, 30.0) << out;
    EXPECT_EQ(out.find("weighted by surface area") != std::string::npos, weight == "area") << out;
  }
  // Encoded by area, the report says whose dB its figures are.
  ASSERT_EQ(run_command(cli() + " encode --always-implicit --quality-weight area " + dir + "/s.glb -o " +
                            dir + "/a.glb 2>&1",
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("implicit-uv"), std::string::npos) << out;
  EXPECT_NE(out.find("weigh each face by its 3D area"), std::string::npos) << out;
}

// --layout mixed writes format 1.4 (the solve on cotangent weights), and
// info names the solve the decoder will run.
TEST(Cli, MixedLayoutWritesTheCotangentSolve) {
  const std::string dir = scratch_dir("cli-mixed");
  std::string out;
  ASSERT_EQ(
      run_command(cli() + " sample --shape torus --faces 3000 --texture-size 128 -o " + dir + "/s.glb 2>&1",
                  &out),
      0)
      << out;
  ASSERT_EQ(run_command(cli() + " encode --always-implicit --layout mixed " + dir + "/s.glb -o " + dir +
                            "/e.glb 2>&1",
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(cli() + " info --json " + dir + "/e.glb 2>&1", &out), 0) << out;
  EXPECT_NE(out.find("\"version\": \"1.4\""), std::string::npos) << out;
  EXPECT_NE(out.find("\"cotangent_weights\": true"), std::string::npos) << out;
  EXPECT_NE(out.find("\"arap_rounds\": 32"), std::string::npos) << out;
  EXPECT_EQ(out.find("\"solve_patches\": 0"), std::string::npos) << out;
  ASSERT_EQ(run_command(cli() + " decode " + dir + "/e.glb -o " + dir + "/d.glb 2>&1", &out), 0) << out;
}

// The mixed layout is the default: an encode without --layout is the
// --layout mixed file byte for byte, and --layout unfold asks no solve of
// the decoder.
TEST(Cli, MixedLayoutIsTheDefault) {
  const std::string dir = scratch_dir("cli-layout-default");
  std::string out;
  ASSERT_EQ(
      run_command(cli() + " sample --shape torus --faces 3000 --texture-size 128 -o " + dir + "/s.glb 2>&1",
                  &out),
      0)
      << out;
  for (const char* layout : {"", "--layout mixed", "--layout unfold"}) {
    const std::string name = *layout ? std::string(layout).substr(9) : "default";
    ASSERT_EQ(run_command(cli() + " encode --always-implicit " + layout + " " + dir + "/s.glb -o " + dir +
                              "/" + name + ".glb 2>&1",
                          &out),
              0)
        << out;
  }
  const std::string default_file = file_bytes(dir + "/default.glb");
  EXPECT_FALSE(default_file.empty());
  EXPECT_TRUE(default_file == file_bytes(dir + "/mixed.glb"));
  ASSERT_EQ(run_command(cli() + " info --json " + dir + "/unfold.glb 2>&1", &out), 0) << out;
  EXPECT_NE(out.find("\"solve_patches\": 0"), std::string::npos) << out;
  ASSERT_EQ(run_command(cli() + " info --json " + dir + "/default.glb 2>&1", &out), 0) << out;
  EXPECT_EQ(out.find("\"solve_patches\": 0"), std::string::npos) << out;
}
