// libFuzzer target: whole-file decode. Bytes are read as a glTF/GLB from
// memory (no external files), decoded (Draco, our bitstream, vertex split,
// tangents) and serialised as a GLB, exactly as `gltf-warp decode` does.
// Must never crash, hang or read out of bounds; every failure is one line.
// Seeds: encoded samples (scripts/sanitize writes a few before fuzzing).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "codec/decode/decoder.h"
#include "fuzz_gltf_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  tinygltf::Model model;
  if (!gltfwarp::fuzz::read_model(data, size, model)) return 0;
  gltfwarp::DecodeOptions opt;
  gltfwarp::DecodeReport report;
  const std::string err = gltfwarp::decode_model(model, opt, report);
  if (!err.empty()) {
    if (err.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  gltfwarp::fuzz::write_model(model);
  return 0;
}
