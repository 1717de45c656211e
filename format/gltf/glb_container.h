// The GLB container (glTF 2.0 binary): split a file into its JSON and BIN
// chunks with every length checked against the file, and write one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace gltfwarp {

// The JSON and BIN chunks of a GLB, checked against the container's lengths
// (tinygltf 2.7 lets a BIN chunk's payload reach 8 bytes past the file).
struct GlbParts {
  std::string json;
  const uint8_t* bin = nullptr;
  size_t bin_size = 0;
};

// Checks the header and the chunk lengths against the file's `n` bytes:
// version 2, a non-empty JSON chunk first, at most one BIN chunk used (other
// chunk types skipped). Empty string, or a one-line reason.
std::string split_glb(const uint8_t* d, size_t n, GlbParts& out);

// A GLB tinygltf accepts: header, JSON padded with spaces, BIN (if any)
// padded with zeros, exact lengths. glb_head is everything before the BIN
// bytes, glb_tail the zeros after them, make_glb all of it.
std::string glb_head(std::string json, size_t bin_size);
std::string_view glb_tail(size_t bin_size);
std::string make_glb(std::string json, const uint8_t* bin, size_t bin_size);

}  // namespace gltfwarp
