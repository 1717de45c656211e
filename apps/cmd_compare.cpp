#include <cmath>
#include <cstdio>
#include <string>

#include "apps/commands.h"
#include "codec/encode/texture/surface_compare.h"
#include "format/gltf/gltf_io.h"

namespace gltfwarp::cli {

Runner add_compare(CLI::App& app) {
  struct Args {
    std::string a, b;
    SurfaceCompareOptions opt;
    std::string weight;
  };
  auto args = std::make_shared<Args>();
  app.add_option("source", args->a, "The original .gltf/.glb")->required()->check(CLI::ExistingFile);
  app.add_option("decoded", args->b, "The same scene after encode + decode")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--slot", args->opt.slot, "Material slot to compare")->default_val("baseColorTexture");
  app.add_flag(
      "--lit", args->opt.lit,
      "Compare lighting: the slot (a normal map, e.g. --slot normalTexture) under three lights through each "
      "file's NORMAL and TANGENT");
  app.add_option("--samples", args->opt.samples_per_face,
                 "Samples per triangle; 0 = about one per source texel")
      ->default_val(0)
      ->check(CLI::Range(0, 1000));
  app.add_option("--weight", args->weight,
                 "texel (each source texel alike: a face weighs its UV area) or area (each face its 3D area: "
                 "the surface as an even view of all of it shows it)")
      ->default_val("texel")
      ->check(CLI::IsMember({"texel", "area"}));
  return [args]() {
    tinygltf::Model a, b;
    GltfReadResult ra = read_gltf(args->a, a);
    if (!ra.ok) return fail(ra.error);
    GltfReadResult rb = read_gltf(args->b, b);
    if (!rb.ok) return fail(rb.error);
    if (args->weight == "area") args->opt.weight = SampleWeight::surface_area;
    const SurfaceComparison c = compare_surface(a, b, args->opt);
    if (!c.error.empty()) return fail(c.error);
    std::printf(
        "surface PSNR %.2f dB (RMSE %.3f, max %.0f of 255) over %zu samples on %zu primitives%s%s\n", c.psnr,
        c.rmse, c.max_abs, c.samples, c.primitives,
        args->opt.weight == SampleWeight::surface_area ? ", weighted by surface area" : "",
        c.unmatched_faces ? (", " + std::to_string(c.unmatched_faces) + " faces unmatched").c_str() : "");
    return 0;
  };
}

}  // namespace gltfwarp::cli
