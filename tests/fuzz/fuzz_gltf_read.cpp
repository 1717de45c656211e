// libFuzzer target: the glTF reader on arbitrary bytes (.gltf text or .glb,
// decided by content, no external files), then what every command does
// next with a model it accepted: read every primitive, compact the buffers
// and serialise. Must never crash, hang, read out of bounds or allocate
// past the declared-size limits; a refusal is one line.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "format/gltf/gltf_primitive.h"
#include "fuzz_gltf_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  tinygltf::Model model;
  if (!gltfwarp::fuzz::read_model(data, size, model)) return 0;
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
  gltfwarp::fuzz::write_model(model);
  return 0;
}
