// libFuzzer target: decode_uvs on arbitrary bytes over a small fixed mesh
// (a 6 x 5 saddle grid plus a closed tetrahedron and a degenerate face, so
// the partition coder sees boundaries, non-manifold-free closed parts and
// repeated vertices). Must never crash, hang or read out of bounds; whatever
// decodes must be a valid map with finite UVs.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"

namespace {

gltfwarp::TriMesh fuzz_mesh() {
  gltfwarp::TriMesh m;
  const uint32_t nx = 6, ny = 5;
  for (uint32_t j = 0; j <= ny; ++j)
    for (uint32_t i = 0; i <= nx; ++i) {
      const float x = static_cast<float>(i) / 6.0f, y = static_cast<float>(j) / 5.0f;
      m.positions.insert(m.positions.end(), {x, y, 0.5f * x * y});
    }
  for (uint32_t j = 0; j < ny; ++j)
    for (uint32_t i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  const uint32_t t = m.vertex_count();
  m.positions.insert(m.positions.end(), {2, 0, 0, 3, 0, 0, 2, 1, 0, 2, 0, 1});
  m.indices.insert(m.indices.end(), {t, t + 2, t + 1, t, t + 1, t + 3, t + 1, t + 2, t + 3, t, t + 3, t + 2});
  m.indices.insert(m.indices.end(), {t, t, t + 1});  // degenerate face
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const gltfwarp::TriMesh mesh = fuzz_mesh();
  std::vector<float> uv;
  gltfwarp::UvMap map;
  const gltfwarp::UvStatus s = gltfwarp::decode_uvs(mesh, std::span<const uint8_t>(data, size), uv, &map);
  gltfwarp::UvStreamInfo info;
  (void)gltfwarp::read_uvmap_info(std::span<const uint8_t>(data, size), info);
  if (s == gltfwarp::UvStatus::ok) {
    if (gltfwarp::validate_uvmap(map, mesh) != gltfwarp::UvStatus::ok) std::abort();
    if (uv.size() != size_t{mesh.face_count()} * 6) std::abort();
    for (float v : uv)
      if (!std::isfinite(v)) std::abort();  // the spec promises finite UVs for every valid stream
    // Round trip: what decodes re-encodes to a stream that decodes the same.
    std::vector<uint8_t> again;
    if (gltfwarp::write_uvmap(map, mesh, again) != gltfwarp::UvStatus::ok) std::abort();
    gltfwarp::UvMap back;
    if (gltfwarp::read_uvmap(again, mesh, back) != gltfwarp::UvStatus::ok || !(back == map)) std::abort();
  }
  return 0;
}
