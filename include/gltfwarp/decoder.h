// gltf-warp's decoder interface: read a glTF 2.0 file, rebuild the implicit
// texture coordinates (and tangents) of every primitive that carries
// GLTFWARP_implicit_texcoords, and write a standard glTF any viewer loads.
// Link gltfwarp::decoder (Draco and tinygltf; no image library).
//
//   tinygltf::Model model;
//   gltfwarp::GltfReadResult r = gltfwarp::read_gltf("in.glb", model);
//   gltfwarp::DecodeReport report;
//   if (!r.ok) return fail(r.error);
//   if (gltfwarp::Error e = gltfwarp::decode_model(model, {}, report); e.failed()) return fail(e.message);
//   if (std::string e = gltfwarp::write_gltf(model, "out.glb"); !e.empty()) return fail(e);
#pragma once

#include "codec/decode/decoder.h"  // decode_model, DecodeOptions, DecodeReport
#include "format/gltf/gltf_io.h"   // read_gltf, read_gltf_memory, write_gltf
#include "gltfwarp/texcoords.h"    // decode_texcoords: the same on plain buffers
