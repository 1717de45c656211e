#include <cstdio>

#include "apps/commands.h"
#include "format/gltf/gltf_io.h"
#include "tests/support/testing/sample_model.h"

namespace gltfwarp::cli {

Runner add_sample(CLI::App& app) {
  struct Args {
    std::string name = "twisted-cone", out;
    int faces = 6000, texture = 512;
  };
  auto a = std::make_shared<Args>();
  app.add_option("-o,--output", a->out, "Output file (.glb or .gltf)")->required();
  app.add_option("--shape", a->name, "Which shape")
      ->default_val("twisted-cone")
      ->check(CLI::IsMember(sample_model_names()));
  app.add_option("--faces", a->faces, "About this many triangles")
      ->default_val(6000)
      ->check(CLI::Range(8, 20000000));
  app.add_option("--texture-size", a->texture, "Side of the square PNG texture")
      ->default_val(512)
      ->check(CLI::Range(8, 16384));
  return [a]() {
    tinygltf::Model model;
    std::string err = make_sample_model(a->name, a->faces, a->texture, model);
    if (!err.empty()) return fail(err);
    err = write_gltf(model, a->out);
    if (!err.empty()) return fail(err);
    std::printf("wrote %s: %s, %zu triangles, %dx%d texture\n", a->out.c_str(), a->name.c_str(),
                model.accessors[model.meshes[0].primitives[0].indices].count / 3, a->texture, a->texture);
    return 0;
  };
}

}  // namespace gltfwarp::cli
