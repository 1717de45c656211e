// glTF container I/O: read .gltf (external files, data URIs) and .glb into a
// tinygltf::Model, write either form chosen by the output's extension.
// Everything the codec does not own passes through: images keep their
// original bytes (never decoded and re-encoded here), extensions and extras
// are carried as tinygltf Values.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "format/gltf/buffer_compaction.h"  // compact_buffers, which write_gltf runs

namespace gltfwarp {

struct GltfReadResult {
  bool ok = false;
  std::string error;    // one line, empty when ok
  std::string warning;  // tinygltf's warnings, joined
};

// Sane limits on what a file may declare; anything past them is refused
// before it is allocated.
inline constexpr size_t kMaxJsonDepth = 64;                       // nesting of JSON arrays/objects
inline constexpr size_t kMaxExternalFileBytes = size_t{1} << 31;  // one .bin or image file

struct GltfReadOptions {
  std::string base_dir = ".";        // where relative URIs resolve
  std::string name = "<memory>";     // what error messages call the input
  bool allow_external_files = true;  // false: only GLB-embedded data and data URIs (fuzzing)
};

// Loads `path` (.gltf or .glb, decided by content). Images are kept as their
// encoded bytes in Image::image with Image::as_is = true. External files
// must be regular files named by relative URIs (no scheme, no absolute
// path); a missing buffer or image file is an error.
GltfReadResult read_gltf(const std::string& path, tinygltf::Model& model);

// The same from bytes in memory (.gltf text or .glb, decided by content).
// The GLB container is checked strictly (version 2, chunk lengths inside the
// file, a JSON chunk first, at most one BIN chunk used), the JSON nesting is
// bounded by kMaxJsonDepth, and every bufferView an image names must lie in
// its buffer, all before tinygltf sees the file.
GltfReadResult read_gltf_memory(const uint8_t* data, size_t size, tinygltf::Model& model,
                                const GltfReadOptions& options = {});

// Writes `model` to `path`: binary when it ends in .glb, else JSON with one
// external "<stem>.bin" buffer. All image bytes move into bufferViews. The
// file appears atomically (temporary file + rename), so a failure leaves no
// partial output. Returns an empty string or a one-line error.
std::string write_gltf(tinygltf::Model& model, const std::string& path);

}  // namespace gltfwarp
