// libFuzzer target: whole-file decode. Bytes are read as a glTF/GLB from
// memory (no external files), decoded (Draco, our bitstream, vertex split,
// tangents) and serialised as a GLB, exactly as `gltf-warp decode` does.
// Must never crash, hang or read out of bounds; every failure is one line.
// Seeds: encoded samples (scripts/sanitize writes a few before fuzzing).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>

#include <unistd.h>

#include "codec/decoder.h"
#include "format/gltf_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  tinygltf::Model model;
  gltfwarp::GltfReadOptions options;
  options.allow_external_files = false;
  const gltfwarp::GltfReadResult r = gltfwarp::read_gltf_memory(data, size, model, options);
  if (!r.ok) {
    if (r.error.empty() || r.error.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  gltfwarp::DecodeOptions opt;
  gltfwarp::DecodeReport report;
  const std::string err = gltfwarp::decode_model(model, opt, report);
  if (!err.empty()) {
    if (err.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  // Serialised through the CLI's own writer (it works around tinygltf's
  // serialiser), into a per-process scratch file.
  static const std::string out = "/tmp/gltf-warp-fuzz-" + std::to_string(getpid()) + ".glb";
  if (gltfwarp::write_gltf(model, out).find('\n') != std::string::npos) std::abort();
  std::remove(out.c_str());
  return 0;
}
