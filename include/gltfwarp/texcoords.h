// gltf-warp's buffer-level decoder: the implicit texture coordinates of one
// primitive from its decoded geometry and its GLTFWARP_implicit_texcoords
// stream, into caller memory. No glTF, Draco or image library is involved:
// a player that already decoded the geometry (with Draco or otherwise) needs
// only this. Link gltfwarp::decoder (find_package(gltfwarp COMPONENTS decoder)).
//
//   std::vector<float> uv(6 * face_count);
//   gltfwarp::UvStatus s = gltfwarp::decode_texcoords(positions, indices, stream, uv);
//   if (s != gltfwarp::UvStatus::ok) std::fprintf(stderr, "%s\n", gltfwarp::to_string(s));
//
// The format is spec/README.md; every conforming decoder gets these bits.
#pragma once

#include <cstdint>
#include <span>

#include "format/bitstream/uvmap.h"  // UvStatus, to_string(UvStatus)

namespace gltfwarp {

// positions: 3 floats per point, as the primitive's POSITION accessor holds
// them (after Draco decoding, for a Draco primitive). indices: 3 point
// indices per triangle. stream: the bytes of the extension's bufferView.
// corner_uv: caller memory for 2 floats per corner, 6 per triangle, in
// triangle order (a corner's UV; points on patch seams get one UV per side,
// so split them where two corners of one point differ).
// Returns ok, or the first thing wrong with the input: bad_mesh (an index
// past the points, or positions not a multiple of 3), bad_argument
// (corner_uv of the wrong size), or any stream status. On failure corner_uv
// is left unspecified. Never reads outside the given spans.
UvStatus decode_texcoords(std::span<const float> positions, std::span<const uint32_t> indices,
                          std::span<const uint8_t> stream, std::span<float> corner_uv);

}  // namespace gltfwarp
