// glTF container I/O: read .gltf (external files, data URIs) and .glb into a
// tinygltf::Model, write either form chosen by the output's extension.
// Everything the codec does not own passes through: images keep their
// original bytes (never decoded and re-encoded here), extensions and extras
// are carried as tinygltf Values.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace gltfwarp {

struct GltfReadResult {
  bool ok = false;
  std::string error;    // one line, empty when ok
  std::string warning;  // tinygltf's warnings, joined
};

// Loads `path` (.gltf or .glb, decided by content). Images are kept as their
// encoded bytes in Image::image with Image::as_is = true.
GltfReadResult read_gltf(const std::string& path, tinygltf::Model& model);

// Writes `model` to `path`: binary when it ends in .glb, else JSON with one
// external "<stem>.bin" buffer. All image bytes move into bufferViews. The
// file appears atomically (temporary file + rename), so a failure leaves no
// partial output. Returns an empty string or a one-line error.
std::string write_gltf(tinygltf::Model& model, const std::string& path);

// Moves every image's encoded bytes into a bufferView of buffer 0 and
// rebuilds one buffer from the bufferViews that are still referenced.
// Accessors in `replaced` (ones the codec superseded) and data-less accessors
// are dropped when nothing references them any more; every reference the
// glTF core and the known extensions make is renumbered. Other unreferenced
// accessors stay: an extension we do not know might name them.
void compact_buffers(tinygltf::Model& model, const std::vector<int>& replaced = {});

}  // namespace gltfwarp
