// Speed of the partition (encoder) and of the shared layout replay (what the
// decoder runs), on generated bumpy spheres of about 10k, 100k and 1M faces.
// Reports triangles per second.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "codec/core/layout.h"
#include "codec/encode/partition/embed.h"
#include "tests/support/testing/shapes.h"

namespace gltfwarp {
namespace {

const ShapeMesh& mesh_of(int64_t faces) {
  static std::map<int64_t, ShapeMesh> cache;
  auto it = cache.find(faces);
  if (it == cache.end()) {
    const int rings = std::max(4, int(std::sqrt(double(faces) / 4.0)));
    it = cache.emplace(faces, make_bumpy_sphere(2 * rings, rings)).first;
  }
  return it->second;
}

void run_partition(benchmark::State& state, PartitionMode mode) {
  const TriMesh& m = mesh_of(state.range(0)).mesh;
  EmbedOptions opt;
  opt.mode = mode;
  uint32_t patches = 0, seams = 0, holes = 0;
  double fill = 0;
  for (auto _ : state) {
    const Embedding e = embed(m, opt);
    patches = e.patch_count;
    seams = e.report.seam_edges;
    holes = e.report.holes;
    fill = e.report.fill;
    benchmark::DoNotOptimize(e.corner_xy.data());
  }
  state.counters["triangles/s"] =
      benchmark::Counter(double(m.face_count()) * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["patches"] = patches;
  state.counters["seams"] = seams;  // issue 8: compact's should be at most half of greedy's
  state.counters["fill"] = fill;
  state.counters["holes"] = holes;
}

void BM_PartitionCompact(benchmark::State& s) { run_partition(s, PartitionMode::compact); }
void BM_PartitionGreedy(benchmark::State& s) { run_partition(s, PartitionMode::greedy); }

void BM_Replay(benchmark::State& state) {
  const TriMesh& m = mesh_of(state.range(0)).mesh;
  EmbedOptions opt;
  const Embedding e = embed(m, opt);
  std::vector<double> xy;
  for (auto _ : state) {
    const LayoutStatus s = layout_patches(m, e.patch_of_face, e.patch_count, xy, e.seeds, e.methods, e.solve);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(xy.data());
  }
  state.counters["triangles/s"] =
      benchmark::Counter(double(m.face_count()) * state.iterations(), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_PartitionCompact)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PartitionGreedy)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Replay)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace gltfwarp
