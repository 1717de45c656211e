// The decoder: rebuilds TEXCOORD_0 (and tangents) from the decoded geometry
// and our bitstream, and writes a standard glTF 2.0 scene any viewer loads.
#pragma once

#include <string>

#include <tiny_gltf.h>

#include "format/gltf/draco_geometry.h"

namespace gltfwarp {

struct DecodeOptions {
  bool keep_draco = false;  // keep geometry Draco-compressed (UVs then go into Draco too)
  DracoOptions draco;       // used only with keep_draco
};

struct DecodeReport {
  size_t primitives_decoded = 0;  // Draco primitives expanded
  size_t uv_maps_rebuilt = 0;     // primitives whose UVs came from our bitstream
};

// Decodes `model` in place. Empty string or a one-line error.
std::string decode_model(tinygltf::Model& model, const DecodeOptions& options, DecodeReport& report);

}  // namespace gltfwarp
