// libFuzzer target: whole-file encode. Bytes are read as a glTF/GLB from
// memory (no external files) and encoded as `gltf-warp encode
// --always-implicit` would, on a small atlas so that each input takes
// milliseconds (Draco, the partition, the layout, packing, the warp, the
// image coders and the quality measures), then serialised. Must never
// crash, hang or read out of bounds; every refusal is one line.
// Seeds: plain and encoded samples (scripts/sanitize writes a few).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "codec/encode/encoder.h"
#include "fuzz_gltf_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  tinygltf::Model model;
  if (!gltfwarp::fuzz::read_model(data, size, model)) return 0;
  gltfwarp::EncodeOptions options;
  options.max_atlas_size = 128;
  options.max_pages = 2;
  options.quality_fallback = false;  // always implicit: the warp runs on whatever partitions
  options.density_boosts.clear();
  options.adaptive_rounds = 1;
  gltfwarp::EncodeReport report;
  const std::string err = gltfwarp::encode_model(model, options, report).message;
  if (!err.empty()) {
    if (err.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  gltfwarp::fuzz::write_model(model);
  return 0;
}
