// What the whole-file fuzz targets share: reading arbitrary bytes as a glTF
// from memory, and serialising an accepted model through the CLI's writer.
// Every refusal must be one line; anything else aborts (a finding).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

#include "format/gltf/gltf_io.h"

namespace gltfwarp::fuzz {

// True when the reader accepted the bytes (no external files).
inline bool read_model(const uint8_t* data, size_t size, tinygltf::Model& model) {
  GltfReadOptions options;
  options.allow_external_files = false;
  const GltfReadResult r = read_gltf_memory(data, size, model, options);
  if (!r.ok && (r.error.empty() || r.error.find('\n') != std::string::npos)) std::abort();
  return r.ok;
}

// Serialised through the CLI's own writer (it works around tinygltf's
// serialiser), into a per-process scratch file that is removed again.
inline void write_model(tinygltf::Model& model) {
  static const std::string out = "/tmp/gltf-warp-fuzz-" + std::to_string(getpid()) + ".glb";
  if (write_gltf(model, out).find('\n') != std::string::npos) std::abort();
  std::remove(out.c_str());
}

}  // namespace gltfwarp::fuzz
