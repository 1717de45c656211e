// libgltf-warp-imaging.so: the verbs that warp and code images (encode,
// sample, compare), loaded by the gltf-warp executable for them.
#include <cstring>

#include "apps/commands.h"

extern "C" __attribute__((visibility("default"))) int gltfwarp_imaging_main(int argc, char** argv) {
  using namespace gltfwarp::cli;
  std::vector<Verb> verbs = all_verbs();
  for (Verb& v : verbs) {
    if (std::strcmp(v.name, "encode") == 0) v.add = add_encode;
    if (std::strcmp(v.name, "sample") == 0) v.add = add_sample;
    if (std::strcmp(v.name, "compare") == 0) v.add = add_compare;
  }
  CLI::App app{"gltf-warp: glTF 2.0 codec that stores textured meshes without explicit texture coordinates"};
  return run_verbs(app, verbs, argc, argv);
}
