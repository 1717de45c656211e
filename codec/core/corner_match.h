// Maps the corners of the Draco-decoded mesh back to the source corners.
// Draco quantizes positions and reorders points and faces (edgebreaker), so
// the encoder finds, for every decoded face, the source face whose corners
// lie within the quantization error, and the rotation between them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gltfwarp {

struct CornerMatch {
  std::vector<uint32_t> source_corner;  // per decoded corner: 3 * source face + k
  size_t unmatched_faces = 0;           // decoded faces with no source face in tolerance
};

// Positions are xyz floats. `tolerance` is the largest distance a decoded
// position may lie from its source (e.g. the quantization step).
CornerMatch match_corners(const std::vector<float>& source_positions,
                          const std::vector<uint32_t>& source_triangles,
                          const std::vector<float>& decoded_positions,
                          const std::vector<uint32_t>& decoded_triangles, double tolerance);

}  // namespace gltfwarp
