// gltf-warp's encoder interface: replace TEXCOORD_0 of every primitive whose
// material samples textures through it by the implicit map, warp those
// textures into atlases, write the geometry as Draco. Link gltfwarp::encoder.
//
//   tinygltf::Model model;  // from gltfwarp::read_gltf (decoder.h)
//   gltfwarp::EncodeReport report;
//   gltfwarp::Error e = gltfwarp::encode_model(model, gltfwarp::EncodeOptions{}, report);
//   if (e.failed()) return fail(e.message);  // e.code: invalid_input or internal (codec/core/error.h)
//   if (std::string w = gltfwarp::write_gltf(model, "out.glb"); !w.empty()) return fail(w);
#pragma once

#include "codec/encode/encoder.h"  // encode_model, EncodeOptions, EncodeReport
#include "gltfwarp/decoder.h"
