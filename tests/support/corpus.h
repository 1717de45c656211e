// Locating the shared corpus (../shared/corpus beside the checkout) and the
// tools the tests run. A test that needs the corpus and does not find it
// fails on CI (CI=true) and skips elsewhere, saying why.
#pragma once

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace gltfwarp::test {

struct CorpusModel {
  std::string name;  // e.g. "Duck"
  std::string path;  // .gltf or .glb
};

// Empty when the corpus is absent.
std::string corpus_dir();
std::vector<CorpusModel> corpus_models();
// The .gltf or .glb of the corpus model `name` (as CorpusModel::name); empty when absent.
std::string corpus_path(const std::string& name);

// Runs a shell command, returns its exit code and stdout.
int run_command(const std::string& cmd, std::string* out = nullptr);

// A fresh empty directory under the build tree for one test's outputs.
std::string scratch_dir(const std::string& name);

struct ValidatorResult {
  bool ran = false;
  int errors = -1;
  std::string codes_json;  // {"CODE": n, ...}
  std::string raw;
};
// Runs the Khronos validator (tools/validate.mjs); ran=false if node or the
// package is missing.
ValidatorResult validate(const std::string& path);

bool on_ci();

}  // namespace gltfwarp::test

// Fails on CI, skips elsewhere.
#define GLTFWARP_REQUIRE_CORPUS()                                                                \
  do {                                                                                           \
    if (::gltfwarp::test::corpus_dir().empty()) {                                                \
      if (::gltfwarp::test::on_ci()) FAIL() << "corpus not found at ../shared/corpus (CI=true)"; \
      GTEST_SKIP() << "corpus not found at ../shared/corpus";                                    \
    }                                                                                            \
  } while (0)
