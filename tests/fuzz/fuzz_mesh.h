// The small fixed mesh fuzz_decode_uvs decodes over: a 6 x 5 saddle grid
// plus a closed tetrahedron and a degenerate face, so the partition coder
// sees boundaries, closed parts and repeated vertices. Shared with the unit
// tests, which replay the fuzzer's findings on it.
#pragma once

#include <cstdint>

#include "codec/core/mesh.h"
#include "tests/test_bitstream_util.h"

namespace gltfwarp {

inline TriMesh fuzz_mesh() {
  TriMesh m = testutil::make_grid(6, 5, 0.5f);
  const uint32_t t = m.vertex_count();
  m.positions.insert(m.positions.end(), {2, 0, 0, 3, 0, 0, 2, 1, 0, 2, 0, 1});
  m.indices.insert(m.indices.end(), {t, t + 2, t + 1, t, t + 1, t + 3, t + 1, t + 2, t + 3, t, t + 3, t + 2});
  m.indices.insert(m.indices.end(), {t, t, t + 1});  // degenerate face
  return m;
}

}  // namespace gltfwarp
