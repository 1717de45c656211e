// libFuzzer target: decode_uvs on arbitrary bytes over a small fixed mesh
// (fuzz_mesh.h). Must never crash, hang or read out of bounds; whatever
// decodes must be a valid map with finite UVs.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "fuzz_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const gltfwarp::TriMesh mesh = gltfwarp::fuzz_mesh();
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
