// Rate control's time with and without the layout memo (group_atlas.h):
// each iteration encodes a generated model at a JPEG target both ways, in
// this process, and checks that the two files are the same. Counters: the
// seconds of each, and their ratio (memo / none; below 1 is the saving).
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "codec/encode/encoder.h"
#include "tests/support/testing/sample_model.h"

namespace gltfwarp {
namespace {

double encode_seconds(const tinygltf::Model& source, bool memo, tinygltf::Model& out, std::string& error) {
  out = source;
  EncodeOptions o;
  o.image_format = "jpeg";
  o.goal_psnr = 44;
  o.layout_memo = memo;
  EncodeReport report;
  const auto t0 = std::chrono::steady_clock::now();
  if (const Error e = encode_model(out, o, report); e.failed()) error = e.message;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

constexpr const char* kModels[] = {"torus", "bumpy-sphere", "twisted-cone"};

void BM_RateControlLayoutMemo(benchmark::State& state) {
  tinygltf::Model source;
  if (const std::string e = make_sample_model(kModels[state.range(0)], int(state.range(1)), 512, source);
      !e.empty()) {
    state.SkipWithError(e.c_str());
    return;
  }
  double with = 0, without = 0;
  {
    tinygltf::Model warm;  // the first encode in a process also loads and sets up libraries
    std::string error;
    encode_seconds(source, true, warm, error);
  }
  for (auto _ : state) {
    tinygltf::Model a, b;
    std::string error;
    with += encode_seconds(source, true, b, error);
    without += encode_seconds(source, false, a, error);
    if (!error.empty()) {
      state.SkipWithError(error.c_str());
      return;
    }
    if (!(a == b)) {
      state.SkipWithError("the memo changed the file");
      return;
    }
  }
  const double n = double(state.iterations());
  state.counters["memo_s"] = with / n;
  state.counters["no_memo_s"] = without / n;
  state.counters["memo/none"] = without > 0 ? with / without : 0;
}

BENCHMARK(BM_RateControlLayoutMemo)
    ->ArgNames({"model", "faces"})
    ->Args({0, 6000})
    ->Args({1, 6000})
    ->Args({2, 6000})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace gltfwarp
