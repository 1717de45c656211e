// libFuzzer target: the glTF reader on arbitrary bytes (.gltf text or .glb,
// decided by content, no external files), then what every command does
// next with a model it accepted: read every primitive, compact the buffers
// and serialise. Must never crash, hang, read out of bounds or allocate
// past the declared-size limits; a refusal is one line.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>

#include <unistd.h>

#include "format/gltf_io.h"
#include "format/gltf_primitive.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  tinygltf::Model model;
  gltfwarp::GltfReadOptions options;
  options.allow_external_files = false;
  const gltfwarp::GltfReadResult r = gltfwarp::read_gltf_memory(data, size, model, options);
  if (!r.ok) {
    if (r.error.empty() || r.error.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  for (const auto& mesh : model.meshes)
    for (const auto& prim : mesh.primitives) {
      gltfwarp::PrimitiveGeometry geom;
      if (!gltfwarp::is_triangle_mode(prim.mode)) continue;
      const std::string err = gltfwarp::read_primitive(model, prim, geom);
      if (!err.empty()) {
        if (err.find('\n') != std::string::npos) std::abort();
        continue;
      }
      for (uint32_t v : geom.triangles)
        if (v >= geom.vertex_count()) std::abort();
    }
  // Serialised through the CLI's own writer (it works around tinygltf's
  // serialiser), into a per-process scratch file.
  static const std::string out = "/tmp/gltf-warp-fuzz-" + std::to_string(getpid()) + ".glb";
  if (gltfwarp::write_gltf(model, out).find('\n') != std::string::npos) std::abort();
  std::remove(out.c_str());
  return 0;
}
