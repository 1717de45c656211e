// decode_consumer IN OUT: decodes a gltf-warp file through the installed
// package's decoder component, and checks the buffer-level decoder's errors.
#include <gltfwarp/decoder.h>

#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t indices[3] = {0, 1, 2};
  const uint8_t garbage[4] = {'n', 'o', 'p', 'e'};
  std::vector<float> uv(6);
  if (gltfwarp::decode_texcoords(positions, indices, garbage, uv) != gltfwarp::UvStatus::bad_magic) return 3;
  tinygltf::Model model;
  const gltfwarp::GltfReadResult r = gltfwarp::read_gltf(argv[1], model);
  gltfwarp::DecodeReport report;
  std::string error = r.error;
  if (r.ok)
    if (const gltfwarp::Error e = gltfwarp::decode_model(model, {}, report); e.failed()) error = e.message;
  if (error.empty()) error = gltfwarp::write_gltf(model, argv[2]);
  if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());
  std::printf("uv maps rebuilt: %zu\n", report.uv_maps_rebuilt);
  return error.empty() && report.uv_maps_rebuilt > 0 ? 0 : 1;
}
