// `gltf-warp encode DIR --out-dir OUT` as an asset pipeline runs it: a
// library of good and malformed files, the JSON-lines report, the exit
// status, resume (a rerun skips), --force, byte-identical outputs whatever
// --jobs, and --shard i/n splitting the list with no overlap.
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/corpus.h"

using namespace gltfwarp::test;
namespace fs = std::filesystem;

namespace {

std::string cli() { return GLTFWARP_CLI; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The report's lines, by input.
std::map<std::string, nlohmann::json> read_report(const std::string& path) {
  std::map<std::string, nlohmann::json> lines;
  std::istringstream in(slurp(path));
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    EXPECT_TRUE(j.is_object()) << line;
    if (!j.is_object()) continue;
    const std::string input = j.value("input", "");
    EXPECT_EQ(lines.count(input), 0u) << "twice: " << input;
    lines[input] = j;
  }
  return lines;
}

// Every file below `dir` with its bytes (relative path -> content).
std::map<std::string, std::string> tree(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).generic_string()] = slurp(e.path());
  return files;
}

struct Library {
  std::string root, lib;
  std::set<std::string> good, bad;  // inputs as the report names them
};

// Built per test (ctest runs tests in parallel processes): three small good models (a generated .glb, a
// generated .gltf with its .bin, the corpus Duck as .gltf + .bin + .png when the corpus is here) and three
// malformed ones, plus a file that is not glTF.
Library make_library(const std::string& name) {
  {
    Library l;
    l.root = scratch_dir(name);
    l.lib = l.root + "/lib";
    fs::create_directories(l.lib + "/sub/deeper");
    fs::create_directories(l.lib + "/bad");
    std::string out;
    EXPECT_EQ(run_command(cli() + " sample --shape torus --faces 600 --texture-size 64 -o " + l.lib +
                              "/torus.glb 2>&1",
                          &out),
              0)
        << out;
    EXPECT_EQ(
        run_command(
            cli() + " sample --faces 400 --texture-size 64 -o " + l.lib + "/sub/deeper/cone.gltf 2>&1", &out),
        0)
        << out;
    l.good = {l.lib + "/torus.glb", l.lib + "/sub/deeper/cone.gltf"};
    if (!corpus_dir().empty()) {
      fs::create_directories(l.lib + "/sub/duck");
      for (const auto& e : fs::directory_iterator(corpus_dir() + "/Duck/glTF"))
        fs::copy_file(e.path(), l.lib + "/sub/duck/" + e.path().filename().string());
      l.good.insert(l.lib + "/sub/duck/Duck.gltf");
    }
    const std::string glb = slurp(l.lib + "/torus.glb");
    std::ofstream(l.lib + "/bad/truncated.glb", std::ios::binary) << glb.substr(0, glb.size() / 2);
    std::ofstream(l.lib + "/bad/garbage.glb") << "this is not a binary glTF at all";
    std::ofstream(l.lib + "/bad/missing_buffer.gltf")
        << R"({"asset":{"version":"2.0"},"buffers":[{"uri":"nowhere.bin","byteLength":64}],)"
        << R"("bufferViews":[{"buffer":0,"byteLength":64}],"meshes":[],"scenes":[{"nodes":[]}]})";
    std::ofstream(l.lib + "/notes.txt") << "not a model";
    l.bad = {l.lib + "/bad/truncated.glb", l.lib + "/bad/garbage.glb", l.lib + "/bad/missing_buffer.gltf"};
    return l;
  }
}

// --always-implicit: these small textures would otherwise keep explicit UVs
// (smaller), and the report's PSNR would go unexercised.
int encode(const std::string& args, std::string* err = nullptr) {
  std::string out;
  const int code = run_command(cli() + " encode --always-implicit " + args + " 2>&1", &out);
  if (err) *err = out;
  return code;
}

}  // namespace

TEST(BatchEncode, ReportResumeForceAndByteIdenticalOutputs) {
  const Library l = make_library("batch-report");
  const std::string out = l.root + "/out", report = l.root + "/r1.jsonl";
  std::string log;
  // 1. First run: the bad files fail, the good ones are encoded, the exit status says so.
  const int code = encode(l.lib + " --out-dir " + out + " --jobs 2 --report " + report, &log);
  EXPECT_EQ(code, 1) << log;
  auto lines = read_report(report);
  EXPECT_EQ(lines.size(), l.good.size() + l.bad.size()) << slurp(report);
  for (const auto& in : l.good) {
    ASSERT_TRUE(lines.count(in)) << in << "\n" << slurp(report);
    const auto& j = lines[in];
    EXPECT_EQ(j["status"], "ok") << j.dump();
    EXPECT_GT(j["bytes_in"].get<uint64_t>(), 0u);
    EXPECT_GT(j["bytes_out"].get<uint64_t>(), 0u);
    EXPECT_GE(j["seconds"].get<double>(), 0.0);
    const auto& h = j["handling"];
    EXPECT_EQ(h["implicit"].get<int>() + h["explicit"].get<int>() + h["untouched"].get<int>(),
              j["primitives"].get<int>())
        << j.dump();
    EXPECT_GT(j["primitives"].get<int>(), 0);
    EXPECT_TRUE(fs::exists(j["output"].get<std::string>())) << j.dump();
    EXPECT_GT(h["implicit"].get<int>(), 0) << j.dump();  // --always-implicit
    if (h["implicit"].get<int>() > 0) {
      EXPECT_GT(j["psnr_db"].get<double>(), 20.0) << j.dump();
    }
    // Each atlas kept carries its equal-quality comparison (issue 16, honest reports).
    const auto& eq = j["equal_quality"];
    ASSERT_TRUE(eq.is_object()) << j.dump();
    EXPECT_EQ(eq["atlases"].size(), size_t(j["atlases"].get<int>())) << j.dump();
    for (const auto& a : eq["atlases"]) {
      EXPECT_GT(a["bytes"].get<uint64_t>(), 0u) << j.dump();
      EXPECT_GT(a["explicit_bytes"].get<uint64_t>(), 0u) << j.dump();
      EXPECT_FALSE(a["explicit_images"].get<std::string>().empty()) << j.dump();
    }
  }
  for (const auto& in : l.bad) {
    ASSERT_TRUE(lines.count(in)) << in;
    EXPECT_EQ(lines[in]["status"], "error");
    EXPECT_FALSE(lines[in].value("error", "").empty()) << lines[in].dump();
    EXPECT_FALSE(fs::exists(lines[in]["output"].get<std::string>()));
  }
  // Mirrored paths; a .gltf input writes .gltf + .bin; non-glTF files are not inputs.
  EXPECT_TRUE(fs::exists(out + "/torus.glb"));
  EXPECT_TRUE(fs::exists(out + "/sub/deeper/cone.gltf"));
  EXPECT_TRUE(fs::exists(out + "/sub/deeper/cone.bin"));
  EXPECT_FALSE(fs::exists(out + "/notes.txt"));
  // Not a terminal: one plain line per file, and a summary.
  EXPECT_NE(log.find("] ok"), std::string::npos) << log;
  EXPECT_NE(log.find("] error"), std::string::npos) << log;
  EXPECT_NE(log.find(std::to_string(l.good.size()) + " encoded"), std::string::npos) << log;
  const auto first = tree(out);

  // 2. Rerun: every good output is current and skipped, untouched.
  EXPECT_EQ(encode(l.lib + " --out-dir " + out + " --jobs 2 --report " + report, &log), 1) << log;
  lines = read_report(report);
  for (const auto& in : l.good) EXPECT_EQ(lines[in]["status"], "skipped") << lines[in].dump();
  for (const auto& in : l.bad) EXPECT_EQ(lines[in]["status"], "error");
  EXPECT_EQ(tree(out), first);

  // 3. A newer input is redone, the others still skipped.
  fs::last_write_time(l.lib + "/torus.glb", fs::file_time_type::clock::now() + std::chrono::seconds(5));
  EXPECT_EQ(encode(l.lib + " --out-dir " + out + " --jobs 2 --report " + report, &log), 1) << log;
  lines = read_report(report);
  EXPECT_EQ(lines[l.lib + "/torus.glb"]["status"], "ok");
  EXPECT_EQ(lines[l.lib + "/sub/deeper/cone.gltf"]["status"], "skipped");

  // 4. --force with --jobs 1, into the same folder and into a fresh one:
  //    everything redone, byte for byte the same as the --jobs 2 run.
  EXPECT_EQ(encode(l.lib + " --out-dir " + out + " --jobs 1 --force --report " + report, &log), 1) << log;
  lines = read_report(report);
  for (const auto& in : l.good) EXPECT_EQ(lines[in]["status"], "ok") << lines[in].dump();
  EXPECT_EQ(tree(out), first);
  const std::string fresh = l.root + "/out-jobs1";
  EXPECT_EQ(encode(l.lib + " --out-dir " + fresh + " --jobs 1 -q", &log), 1) << log;
  EXPECT_EQ(tree(fresh), first);
  // -q: only the failures and the summary.
  EXPECT_EQ(log.find("] ok"), std::string::npos) << log;
  EXPECT_NE(log.find("] error"), std::string::npos) << log;
}

TEST(BatchEncode, ShardsSplitTheListWithNoOverlap) {
  const Library l = make_library("batch-shards");
  std::set<std::string> all;
  all.insert(l.good.begin(), l.good.end());
  all.insert(l.bad.begin(), l.bad.end());
  std::set<std::string> seen;
  std::vector<size_t> sizes;
  for (int i = 0; i < 2; ++i) {
    const std::string report = l.root + "/shard" + std::to_string(i) + ".jsonl";
    std::string log;
    encode(l.lib + " --out-dir " + l.root + "/out-shards --jobs 2 --shard " + std::to_string(i) +
               "/2 --report " + report,
           &log);
    const auto lines = read_report(report);
    sizes.push_back(lines.size());
    for (const auto& [input, j] : lines) {
      EXPECT_TRUE(seen.insert(input).second) << input << " in two shards";
      EXPECT_TRUE(all.count(input)) << input;
    }
  }
  EXPECT_EQ(seen, all);
  EXPECT_LE(std::max(sizes[0], sizes[1]) - std::min(sizes[0], sizes[1]), 1u);
}

TEST(BatchEncode, ArgumentErrorsAreOneLine) {
  // Arguments are checked before any file is read: two placeholder inputs do.
  const std::string root = scratch_dir("batch-args"), lib = root + "/lib";
  fs::create_directories(lib);
  std::ofstream(lib + "/a.glb") << "a";
  std::ofstream(lib + "/b.gltf") << "b";
  for (const std::string& args :
       {lib + " -o " + root + "/x.glb",  // a directory needs --out-dir
        lib + "/a.glb " + lib + "/b.gltf -o " + root + "/x.glb",
        lib + " --out-dir " + root + "/o --shard 2/2", lib + " --out-dir " + root + "/o --shard x",
        lib + " --out-dir " + root + "/o --jobs 0", lib + " --out-dir " + root + "/o -o " + root + "/x.glb",
        lib + "/a.glb"}) {  // neither -o nor --out-dir
    std::string log;
    EXPECT_EQ(run_command(cli() + " encode " + args + " 2>&1 >/dev/null", &log), 2) << args << "\n" << log;
    EXPECT_EQ(log.rfind("gltf-warp: ", 0), 0u) << log;
    EXPECT_EQ(log.find('\n'), log.size() - 1) << log;
  }
  EXPECT_FALSE(fs::exists(root + "/o"));
  EXPECT_FALSE(fs::exists(root + "/x.glb"));
}

TEST(BatchEncode, TwoInputsForOneOutputFailTheSecond) {
  // x.gltf and x.glb both become x.glb with --container glb: the first in
  // the sorted list keeps the output, the second fails without running.
  // Placeholder files: both fail, each for its own reason.
  const std::string root = scratch_dir("batch-collide"), lib = root + "/lib";
  fs::create_directories(lib);
  std::ofstream(lib + "/x.glb") << "x";
  std::ofstream(lib + "/x.gltf") << "x";
  std::string log;
  EXPECT_EQ(encode(lib + " --out-dir " + root + "/out --container glb --report " + root + "/r.jsonl", &log),
            1)
      << log;
  auto lines = read_report(root + "/r.jsonl");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[lib + "/x.glb"]["output"], root + "/out/x.glb");
  EXPECT_EQ(lines[lib + "/x.gltf"]["output"], root + "/out/x.glb");
  EXPECT_NE(lines[lib + "/x.gltf"].value("error", "").find("also " + lib + "/x.glb"), std::string::npos)
      << lines[lib + "/x.gltf"].dump();
  EXPECT_NE(lines[lib + "/x.glb"].value("error", "").find("cannot read"), std::string::npos)
      << lines[lib + "/x.glb"].dump();
}
