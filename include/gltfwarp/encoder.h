// gltf-warp's encoder interface: replace TEXCOORD_0 of every primitive whose
// material samples textures through it by the implicit map, warp those
// textures into atlases, write the geometry as Draco. Link gltfwarp::encoder.
//
//   tinygltf::Model model;  // from gltfwarp::read_gltf (decoder.h)
//   gltfwarp::EncodeReport report;
//   std::string error = gltfwarp::encode_model(model, gltfwarp::EncodeOptions{}, report);
//   if (error.empty()) error = gltfwarp::write_gltf(model, "out.glb");
#pragma once

#include "codec/encode/encoder.h"  // encode_model, EncodeOptions, EncodeReport
#include "gltfwarp/decoder.h"
