// The glTF extension that carries our bitstream: names of the extension and
// of its JSON members. spec/README.md ("glTF extension") and
// spec/GLTFWARP_implicit_texcoords.schema.json are normative.
//
// On a mesh primitive, next to KHR_draco_mesh_compression when present:
//   "extensions": { "GLTFWARP_implicit_texcoords": {
//       "bufferView": 7,       // bitstream bytes (uvmap_codec.h)
//       "texCoord": 0,         // the TEXCOORD_n set it replaces
//       "atlasWidth": 2048, "atlasHeight": 2048 } }   // echo of the stream header
// The extension goes in extensionsUsed, and in extensionsRequired unless the
// primitive also carries explicit (fallback) TEXCOORD_n.
#pragma once

namespace gltfwarp::ext {

inline constexpr const char* kName = "GLTFWARP_implicit_texcoords";
inline constexpr const char* kBufferView = "bufferView";
inline constexpr const char* kTexCoord = "texCoord";
inline constexpr const char* kAtlasWidth = "atlasWidth";
inline constexpr const char* kAtlasHeight = "atlasHeight";
// The extension it sits beside, whose decoded mesh it applies to.
inline constexpr const char* kDracoName = "KHR_draco_mesh_compression";

}  // namespace gltfwarp::ext
