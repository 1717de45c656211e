// Warp throughput (texels per second, OIIO filtered lookups) and packing time
// per patch, on generated inputs.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "codec/encode/atlas/pack.h"
#include "codec/encode/texture/warp.h"

namespace gltfwarp {
namespace {

OIIO::ImageBuf noise_image(int size) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(size, size, 3, OIIO::TypeDesc::UINT8));
  auto* p = static_cast<uint8_t*>(buf.localpixels());
  std::mt19937 rng(1);
  for (size_t i = 0; i < size_t(size) * size * 3; ++i) p[i] = uint8_t(rng());
  return buf;
}

// k x k square patches, each turned by a small angle, tiling an atlas of
// `atlas` texels; patch (i, j) samples source cell (j, i) (a transposed grid).
struct Tiles {
  std::vector<float> src, dst;
};
Tiles make_tiles(int atlas, int k) {
  Tiles t;
  const double cell = double(atlas) / k, half = cell * 0.45;
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const double a = 0.3 * std::sin(i * 1.7 + j), c = std::cos(a) * 0.95, s = std::sin(a) * 0.95;
      const double cx = (i + 0.5) * cell, cy = (j + 0.5) * cell;
      const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      const int tri[6] = {0, 1, 2, 0, 2, 3};
      for (int v : tri) {
        const double x = corner[v][0] * half, y = corner[v][1] * half;
        t.dst.push_back(float((cx + c * x - s * y) / atlas));
        t.dst.push_back(float((cy + s * x + c * y) / atlas));
        t.src.push_back(float((j + 0.5 + corner[v][0] * 0.45) / k));
        t.src.push_back(float((i + 0.5 + corner[v][1] * 0.45) / k));
      }
    }
  return t;
}

void BM_WarpTexels(benchmark::State& state) {
  const int atlas = int(state.range(0));
  const OIIO::ImageBuf src = noise_image(1024);
  const Tiles tiles = make_tiles(atlas, 16);
  WarpPrimitive p;
  p.source_uv = tiles.src;
  p.atlas_uv = tiles.dst;
  const WarpPrimitive prims[1] = {p};
  WarpOptions opt;
  uint64_t texels = 0;
  for (auto _ : state) {
    OIIO::ImageBuf out;
    WarpReport rep;
    warp_texture(src, prims, uint32_t(atlas), uint32_t(atlas), opt, out, &rep);
    texels += rep.covered_texels + rep.gutter_texels;
  }
  state.counters["texels/s"] = benchmark::Counter(double(texels), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_WarpTexels)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// Packing star-shaped blobs. Arms: trials that cannot win stopped early
// (the default), and every trial run to its end (the baseline: the same
// packing, Pack.StoppingLosingTrialsKeepsThePacking); their times' ratio is
// what the stop saves.
void pack_patches(benchmark::State& state, bool stop_losing_trials) {
  const int n = int(state.range(0));
  TriMesh mesh;
  std::vector<uint32_t> patch_of_face;
  std::vector<double> xy;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  for (int p = 0; p < n; ++p) {  // star-shaped blobs of 10 fan triangles
    const double r0 = 0.5 + u(rng);
    double rad[10];
    for (double& r : rad) r = r0 * (0.5 + 0.5 * u(rng));
    for (int k = 0; k < 10; ++k) {
      const double a0 = 0.6283185 * k, a1 = 0.6283185 * (k + 1);
      const double pts[3][2] = {{0, 0},
                                {rad[k] * std::cos(a0), rad[k] * std::sin(a0)},
                                {rad[(k + 1) % 10] * std::cos(a1), rad[(k + 1) % 10] * std::sin(a1)}};
      for (const auto& q : pts) {
        mesh.indices.push_back(mesh.vertex_count());
        mesh.positions.insert(mesh.positions.end(), {float(q[0]), float(q[1]), 0.0f});
        xy.insert(xy.end(), {q[0], q[1]});
      }
      patch_of_face.push_back(uint32_t(p));
    }
  }
  const PackPrimitive prim{&mesh, patch_of_face, uint32_t(n), xy};
  PackOptions opt;
  opt.texel_scale = 16.0;
  opt.stop_losing_trials = stop_losing_trials;
  double fill = 0, stopped = 0;
  for (auto _ : state) {
    PackResult res;
    pack_atlas({&prim, 1}, opt, res);
    fill = res.report.fill;
    stopped = double(res.report.stopped_trials) / std::max(1u, res.report.trials);
  }
  state.counters["stopped"] = stopped;  // share of the last attempt's trials stopped early
  state.counters["patches/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fill"] = fill;
}
void BM_PackPatches(benchmark::State& s) { pack_patches(s, true); }
void BM_PackPatchesEveryTrialToItsEnd(benchmark::State& s) { pack_patches(s, false); }
BENCHMARK(BM_PackPatches)->Arg(100)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PackPatchesEveryTrialToItsEnd)
    ->Arg(100)
    ->Arg(1000)
    ->Arg(3000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace gltfwarp
