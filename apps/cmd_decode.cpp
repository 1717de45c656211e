#include <chrono>
#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "codec/decode/decoder.h"
#include "format/gltf/gltf_io.h"

namespace gltfwarp::cli {

Runner add_decode(CLI::App& app) {
  struct Args {
    std::string in, out;
    DecodeOptions opt;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  app.add_option("input", a->in, "Encoded .gltf or .glb")->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", a->out, "Output file; .glb or .gltf decides the container")->required();
  app.add_flag("--keep-draco", a->opt.keep_draco,
               "Keep the geometry Draco-compressed (with the rebuilt UVs)");
  app.add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  return [a]() {
    const auto t0 = std::chrono::steady_clock::now();
    tinygltf::Model model;
    GltfReadResult rr = read_gltf(a->in, model);
    if (!rr.ok) return fail(rr.error);
    DecodeReport report;
    std::string err = decode_model(model, a->opt, report);
    if (!err.empty()) return fail(a->in + ": " + err);
    err = write_gltf(model, a->out);
    if (!err.empty()) return fail(err);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!a->quiet) {
      std::error_code ec;
      std::printf("decoded %s -> %s: %zu primitives expanded, %zu UV maps rebuilt, %llu bytes, %.3f s\n",
                  a->in.c_str(), a->out.c_str(), report.primitives_decoded, report.uv_maps_rebuilt,
                  static_cast<unsigned long long>(std::filesystem::file_size(a->out, ec)), secs);
    }
    return 0;
  };
}

}  // namespace gltfwarp::cli
