// Bitstream benchmarks: encode / decode speed of the GWUV stream and of
// decode_uvs, and its size (counters) on real partitions (codec/encode/partition/embed on the
// generated shapes, after a Draco round trip so that the face order is
// Draco's) next to what TEXCOORD_0 costs in Draco at 12 bits on the same
// shape. Also measures the alternative partition coding that the format did
// not adopt (seam flags over edges with neighbour contexts), for the record.
//
// Counters (per shape): faces, verts, patches, part_bpf (partition bits per
// face), place_bpp (placement bits per patch), total_bytes, bpv (stream bits
// per vertex), seamflags_bpf (the alternative), draco12_uv_bytes, ratio
// (stream bytes / Draco-12 UV bytes).
#include <benchmark/benchmark.h>

#include <cstring>
#include <map>
#include <random>

#include "codec/encode/partition/embed.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/range_coder.h"
#include "format/bitstream/uvmap_codec.h"
#include "format/gltf/draco_geometry.h"
#include "format/gltf/gltf_accessors.h"
#include "tests/support/testing/shapes.h"
#include "tests/test_bitstream_util.h"

using namespace gltfwarp;

namespace {

VertexAttribute float_attribute(const std::string& semantic, int components, const std::vector<float>& v) {
  VertexAttribute a;
  a.semantic = semantic;
  a.component_type = 5126;
  a.components = components;
  a.data.resize(v.size() * sizeof(float));
  std::memcpy(a.data.data(), v.data(), a.data.size());
  return a;
}

size_t draco_size(const std::vector<VertexAttribute>& attrs, const std::vector<uint32_t>& tris) {
  const DracoEncoded e = draco_encode(attrs, tris, DracoOptions{});
  return e.error.empty() ? e.bytes.size() : 0;
}

// Draco bytes of positions + TEXCOORD_0 (vertices split at UV seams) minus
// Draco bytes of positions alone: what the UVs cost at 12 bits.
size_t draco12_uv_bytes(const ShapeMesh& s) {
  const TriMesh& m = s.mesh;
  std::map<std::tuple<uint32_t, float, float>, uint32_t> ids;
  std::vector<float> pos, uv;
  std::vector<uint32_t> tris;
  for (uint32_t c = 0; c < m.indices.size(); ++c) {
    const uint32_t v = m.indices[c];
    const auto key = std::make_tuple(v, s.corner_uv[2 * c], s.corner_uv[2 * c + 1]);
    auto it = ids.find(key);
    if (it == ids.end()) {
      it = ids.emplace(key, static_cast<uint32_t>(ids.size())).first;
      pos.insert(pos.end(), {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
      uv.insert(uv.end(), {s.corner_uv[2 * c], s.corner_uv[2 * c + 1]});
    }
    tris.push_back(it->second);
  }
  const size_t with =
      draco_size({float_attribute("POSITION", 3, pos), float_attribute("TEXCOORD_0", 2, uv)}, tris);
  const size_t without = draco_size({float_attribute("POSITION", 3, m.positions)}, m.indices);
  return with > without ? with - without : 0;
}

// The decoded mesh D: positions only, through Draco (its face order).
TriMesh draco_round_trip(const TriMesh& m) {
  const DracoEncoded e =
      draco_encode({float_attribute("POSITION", 3, m.positions)}, m.indices, DracoOptions{});
  const DracoDecoded d =
      draco_decode(e.bytes.data(), e.bytes.size(),
                   {DracoWanted{"POSITION", e.attribute_ids.at("POSITION"), 5126, 3, false}});
  TriMesh out;
  out.positions.resize(d.point_count * 3);
  std::memcpy(out.positions.data(), d.attributes[0].data.data(), out.positions.size() * sizeof(float));
  out.indices = d.triangles;
  return out;
}

// The alternative not adopted: one flag per interior edge (at its higher
// face, faces ascending, k ascending), "different patch", with contexts on
// the flags already coded at this face and on whether the lower face had a seam.
size_t seam_flag_bytes(const TriMesh& m, const std::vector<uint32_t>& patch) {
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> first;
  std::vector<uint8_t> seam_face(m.face_count(), 0);
  rc::Encoder e;
  rc::BitModel ctx[3][2];
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    uint32_t coded = 0;
    for (uint32_t k = 0; k < 3; ++k) {
      uint32_t a = m.indices[3 * f + k], b = m.indices[3 * f + (k + 1) % 3];
      if (a > b) std::swap(a, b);
      auto [it, inserted] = first.emplace(std::make_pair(a, b), f);
      if (inserted || it->second == f) continue;
      const uint32_t g = it->second;
      const uint32_t flag = patch[g] != patch[f];
      e.bit(ctx[std::min(coded, 2u)][seam_face[g]], flag);
      coded += flag;
      if (flag) seam_face[f] = seam_face[g] = 1;
    }
  }
  return e.finish().size();
}

struct Case {
  std::string name;
  TriMesh mesh;
  UvMap map;
  std::vector<uint8_t> bytes;
  UvStreamInfo info;
  size_t draco_uv = 0, seamflags = 0;
};

const std::vector<Case>& cases() {
  static const std::vector<Case> all = [] {
    std::vector<Case> out;
    for (const NamedShape& ns : standard_shapes(2000)) {
      if (ns.name.find("soup") != std::string::npos) continue;
      Case c;
      c.name = ns.name;
      c.mesh = draco_round_trip(ns.shape.mesh);
      const Embedding emb = embed(c.mesh);
      if (emb.status != LayoutStatus::ok) continue;
      c.map.atlas_width = c.map.atlas_height = 1024;
      c.map.texel_scale = 512.0f;
      c.map.patch_count = emb.patch_count;
      c.map.patch_of_face = emb.patch_of_face;
      std::mt19937 rng(1);
      for (uint32_t p = 0; p < c.map.patch_count; ++p)  // uniform-coded: cost is content-independent
        c.map.placements.push_back({static_cast<uint32_t>(rng() % 256), static_cast<int32_t>(rng() % 1025),
                                    static_cast<int32_t>(rng() % 1025), 0, 0});
      c.bytes = write_uvmap(c.map, c.mesh);
      read_uvmap_info(c.bytes, c.info);
      c.draco_uv = draco12_uv_bytes(ns.shape);
      c.seamflags = seam_flag_bytes(c.mesh, c.map.patch_of_face);
      out.push_back(std::move(c));
    }
    return out;
  }();
  return all;
}

void set_counters(benchmark::State& state, const Case& c) {
  const double nf = c.mesh.face_count(), nv = c.mesh.vertex_count();
  state.counters["faces"] = nf;
  state.counters["verts"] = nv;
  state.counters["patches"] = c.map.patch_count;
  state.counters["part_bpf"] = 8.0 * c.info.partition_bytes / nf;
  state.counters["seamflags_bpf"] = 8.0 * c.seamflags / nf;
  state.counters["place_bpp"] = c.map.patch_count ? 8.0 * c.info.placement_bytes / c.map.patch_count : 0;
  state.counters["total_bytes"] = static_cast<double>(c.bytes.size());
  state.counters["bpv"] = 8.0 * c.bytes.size() / nv;
  state.counters["draco12_uv_bytes"] = static_cast<double>(c.draco_uv);
  state.counters["draco12_uv_bpv"] = 8.0 * c.draco_uv / nv;
  state.counters["ratio"] = c.draco_uv ? static_cast<double>(c.bytes.size()) / c.draco_uv : 0;
}

void BM_ReadUvMap_Shape(benchmark::State& state) {
  const Case& c = cases()[state.range(0)];
  state.SetLabel(c.name);
  UvMap out;
  for (auto _ : state) {
    const UvStatus s = read_uvmap(c.bytes, c.mesh, out);
    benchmark::DoNotOptimize(s);
  }
  set_counters(state, c);
  state.SetItemsProcessed(state.iterations() * c.mesh.face_count());
}

void BM_WriteUvMap_Shape(benchmark::State& state) {
  const Case& c = cases()[state.range(0)];
  state.SetLabel(c.name);
  std::vector<uint8_t> bytes;
  for (auto _ : state) {
    const UvStatus s = write_uvmap(c.map, c.mesh, bytes);
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations() * c.mesh.face_count());
}

void BM_DecodeUvs_Shape(benchmark::State& state) {
  const Case& c = cases()[state.range(0)];
  state.SetLabel(c.name);
  std::vector<float> uv;
  for (auto _ : state) {
    const UvStatus s = decode_uvs(c.mesh, c.bytes, uv);
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations() * c.mesh.face_count());
}

void shape_args(benchmark::internal::Benchmark* b) {
  for (size_t i = 0; i < cases().size(); ++i) b->Arg(static_cast<int64_t>(i));
}

// Large synthetic case: a 200 x 125 grid (50k faces), BFS regions of ~500 faces.
struct Big {
  TriMesh mesh = testutil::make_grid(200, 125);
  UvMap map;
  std::vector<uint8_t> bytes;
  Big() {
    std::mt19937 rng(2);
    map = testutil::random_uvmap(mesh, mesh.face_count() / 500, rng, false, false, true);
    bytes = write_uvmap(map, mesh);
  }
};
const Big& big() {
  static const Big b;
  return b;
}

void BM_ReadUvMap_Grid50k(benchmark::State& state) {
  UvMap out;
  for (auto _ : state) benchmark::DoNotOptimize(read_uvmap(big().bytes, big().mesh, out));
  state.SetItemsProcessed(state.iterations() * big().mesh.face_count());
  state.counters["bpf"] = 8.0 * big().bytes.size() / big().mesh.face_count();
  state.counters["patches"] = big().map.patch_count;
}

void BM_WriteUvMap_Grid50k(benchmark::State& state) {
  std::vector<uint8_t> bytes;
  for (auto _ : state) benchmark::DoNotOptimize(write_uvmap(big().map, big().mesh, bytes));
  state.SetItemsProcessed(state.iterations() * big().mesh.face_count());
}

void BM_DecodeUvs_Grid50k(benchmark::State& state) {
  std::vector<float> uv;
  for (auto _ : state) benchmark::DoNotOptimize(decode_uvs(big().mesh, big().bytes, uv));
  state.SetItemsProcessed(state.iterations() * big().mesh.face_count());
}

}  // namespace

BENCHMARK(BM_ReadUvMap_Shape)->Apply(shape_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WriteUvMap_Shape)->Apply(shape_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DecodeUvs_Shape)->Apply(shape_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadUvMap_Grid50k)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteUvMap_Grid50k)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeUvs_Grid50k)->Unit(benchmark::kMillisecond);
