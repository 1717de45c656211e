// decode_texcoords (include/gltfwarp/texcoords.h): the buffer-level decoder.
// Welds the points as every decoder does (embedding_mesh.h), then runs the
// shared decode_uvs.
#include "gltfwarp/texcoords.h"

#include <algorithm>
#include <vector>

#include "codec/decode/embedding_mesh.h"
#include "format/bitstream/decode_uvs.h"

namespace gltfwarp {

UvStatus decode_texcoords(std::span<const float> positions, std::span<const uint32_t> indices,
                          std::span<const uint8_t> stream, std::span<float> corner_uv) {
  if (positions.size() % 3 != 0 || indices.size() % 3 != 0) return UvStatus::bad_mesh;
  if (corner_uv.size() != 2 * indices.size()) return UvStatus::bad_argument;
  const size_t points = positions.size() / 3;
  for (uint32_t i : indices)
    if (i >= points) return UvStatus::bad_mesh;
  std::vector<uint32_t> point_to_vertex;
  const TriMesh mesh = embedding_mesh(positions, indices, point_to_vertex);
  std::vector<float> uv;
  const UvStatus s = decode_uvs(mesh, stream, uv);
  if (s != UvStatus::ok) return s;
  if (uv.size() != corner_uv.size()) return UvStatus::bad_argument;
  std::copy(uv.begin(), uv.end(), corner_uv.begin());
  return UvStatus::ok;
}

}  // namespace gltfwarp
