// gltf-warp's public interface, whole: encoder.h (encode_model), decoder.h
// (read_gltf, decode_model, write_gltf) and texcoords.h (the buffer-level
// decoder). A decoder-only program may include decoder.h or texcoords.h alone
// and link gltfwarp::decoder.
#pragma once

#include "gltfwarp/decoder.h"
#include "gltfwarp/encoder.h"
#include "gltfwarp/texcoords.h"
