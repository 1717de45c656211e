// The decoder's stages on a real encoded file (issue 19, decode budget): the
// Draco decode of every implicit-UV primitive, then the UV rebuild split into
// welding (embedding_mesh), reading the bitstream (read_uvmap), the layout
// replay (layout_patches) and the whole of rebuild_texcoords (weld,
// decode_uvs, vertex split, tangents). Each reports triangles per second, so
// the rebuild's cost reads directly against Draco's in the same process. The
// rates are by wall time: the replay runs ranges of patches on every core
// (layout.h), Draco on one. BM_FileReplay/threads:1 gives the replay's rate
// on one thread, for the per-core figure.
//
//   GLTFWARP_BENCH_MODEL=ours.glb build/gltf-warp-bench --benchmark_filter=BM_File
//
// Without GLTFWARP_BENCH_MODEL these benchmarks skip.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "codec/core/layout.h"
#include "codec/decode/embedding_mesh.h"
#include "codec/decode/implicit_uv_primitive.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_accessors.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {
namespace {

struct DecodedPrimitive {
  const tinygltf::Primitive* prim = nullptr;
  PrimitiveGeometry geom;      // as Draco decodes it, before the rebuild
  TriMesh mesh;                // embedding mesh
  std::vector<uint8_t> bytes;  // the UV bitstream
  UvMap map;
};

struct Model {
  tinygltf::Model model;
  std::vector<DecodedPrimitive> prims;
  size_t triangles = 0;
  std::string error;
};

const Model& model() {
  static const std::unique_ptr<Model> m = [] {
    auto out = std::make_unique<Model>();
    const char* path = std::getenv("GLTFWARP_BENCH_MODEL");
    if (!path) {
      out->error = "set GLTFWARP_BENCH_MODEL to an encoded .glb";
      return out;
    }
    const GltfReadResult r = read_gltf(path, out->model);
    if (!r.ok) {
      out->error = r.error;
      return out;
    }
    for (const auto& mesh : out->model.meshes)
      for (const auto& prim : mesh.primitives) {
        auto it = prim.extensions.find(ext::kName);
        if (it == prim.extensions.end()) continue;
        DecodedPrimitive d;
        d.prim = &prim;
        if (const std::string e = read_primitive(out->model, prim, d.geom); !e.empty()) {
          out->error = e;
          return out;
        }
        std::vector<uint32_t> p2v;
        d.mesh = embedding_mesh(*d.geom.find("POSITION"), d.geom.triangles, p2v);
        const auto& bv = out->model.bufferViews[value_index(it->second.Get("bufferView"))];
        const auto& buf = out->model.buffers[bv.buffer].data;
        d.bytes.assign(buf.begin() + long(bv.byteOffset), buf.begin() + long(bv.byteOffset + bv.byteLength));
        if (read_uvmap(d.bytes, d.mesh, d.map) != UvStatus::ok) {
          out->error = "bad UV bitstream";
          return out;
        }
        out->triangles += d.mesh.face_count();
        out->prims.push_back(std::move(d));
      }
    if (out->prims.empty()) out->error = "no implicit-UV primitive";
    return out;
  }();
  return *m;
}

template <typename Body>
void run(benchmark::State& state, Body&& body) {
  const Model& m = model();
  if (!m.error.empty()) {
    state.SkipWithError(m.error.c_str());
    return;
  }
  for (auto _ : state)
    for (const DecodedPrimitive& d : m.prims) body(m, d);
  state.counters["triangles/s"] =
      benchmark::Counter(double(m.triangles) * double(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_FileDraco(benchmark::State& state) {
  run(state, [](const Model& m, const DecodedPrimitive& d) {
    PrimitiveGeometry g;
    benchmark::DoNotOptimize(read_primitive(m.model, *d.prim, g));
  });
}

void BM_FileWeld(benchmark::State& state) {
  run(state, [](const Model&, const DecodedPrimitive& d) {
    std::vector<uint32_t> p2v;
    const TriMesh mesh = embedding_mesh(*d.geom.find("POSITION"), d.geom.triangles, p2v);
    benchmark::DoNotOptimize(mesh.indices.data());
  });
}

void BM_FileReadUvmap(benchmark::State& state) {
  run(state, [](const Model&, const DecodedPrimitive& d) {
    UvMap map;
    benchmark::DoNotOptimize(read_uvmap(d.bytes, d.mesh, map));
  });
}

// The argument caps the replay's threads (0: every core, 1: the per-core rate).
void BM_FileReplay(benchmark::State& state) {
  std::vector<double> xy;
  const auto threads = uint32_t(state.range(0));
  run(state, [&](const Model&, const DecodedPrimitive& d) {
    benchmark::DoNotOptimize(layout_patches(d.mesh, d.map.patch_of_face, d.map.patch_count, xy, d.map.seeds,
                                            d.map.methods, d.map.solve, threads));
    benchmark::DoNotOptimize(xy.data());
  });
}

void BM_FileDecodeUvs(benchmark::State& state) {
  std::vector<float> uv;
  run(state, [&](const Model&, const DecodedPrimitive& d) {
    benchmark::DoNotOptimize(decode_uvs(d.mesh, d.bytes, uv));
    benchmark::DoNotOptimize(uv.data());
  });
}

void BM_FileRebuildTexcoords(benchmark::State& state) {
  run(state, [](const Model& m, const DecodedPrimitive& d) {
    PrimitiveGeometry g = d.geom;
    benchmark::DoNotOptimize(rebuild_texcoords(m.model, *d.prim, g));
  });
}

BENCHMARK(BM_FileDraco)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FileWeld)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FileReadUvmap)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FileReplay)->ArgName("threads")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FileDecodeUvs)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FileRebuildTexcoords)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace gltfwarp
