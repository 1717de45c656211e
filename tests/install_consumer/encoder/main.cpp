// encode_consumer IN OUT: encodes a textured glTF through the installed
// package's encoder component; fails unless some primitive got the implicit map.
#include <gltfwarp/gltfwarp.h>

#include <algorithm>
#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  tinygltf::Model model;
  const gltfwarp::GltfReadResult r = gltfwarp::read_gltf(argv[1], model);
  gltfwarp::EncodeReport report;
  std::string error = r.error;
  // The generated texture is the method's worst case (detail at every scale,
  // no unused space): with fallbacks on, explicit UVs would be kept.
  gltfwarp::EncodeOptions options;
  options.quality_fallback = false;
  if (r.ok)
    if (const gltfwarp::Error e = gltfwarp::encode_model(model, options, report); e.failed())
      error = e.message;
  if (error.empty()) error = gltfwarp::write_gltf(model, argv[2]);
  if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());
  const auto& used = model.extensionsUsed;
  const bool implicit = std::find(used.begin(), used.end(), "GLTFWARP_implicit_texcoords") != used.end();
  return error.empty() && implicit ? 0 : 1;
}
