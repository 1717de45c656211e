// Buffer compaction before a glTF is written: image bytes move into
// bufferViews, unreferenced data is dropped, and every reference is renumbered.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace gltfwarp {

// Moves every image's encoded bytes into a bufferView of buffer 0 and
// rebuilds one buffer from the bufferViews that are still referenced.
// Accessors in `replaced` (ones the codec superseded) and data-less accessors
// are dropped when nothing references them any more; every reference the
// glTF core and the known extensions make is renumbered. Other unreferenced
// accessors stay: an extension we do not know might name them.
void compact_buffers(tinygltf::Model& model, const std::vector<int>& replaced = {});

// The MIME type of encoded image bytes by their signature (PNG, JPEG, WebP,
// KTX2), else `fallback` (else application/octet-stream).
std::string mime_for_bytes(const std::vector<unsigned char>& bytes, const std::string& fallback);

}  // namespace gltfwarp
