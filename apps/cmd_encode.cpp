#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "apps/batch_encode.h"
#include "apps/batch_options.h"
#include "apps/child_process.h"
#include "apps/commands.h"
#include "apps/encode_summary.h"
#include "apps/report_format.h"
#include "codec/encode/encoder.h"
#include "format/gltf/gltf_io.h"

namespace gltfwarp::cli {

namespace {

enum class Summary { none, table, json };  // json: one line for the batch parent (encode_summary.h)

// Encodes one file; the exit code.
int encode_file(const std::string& in, const std::string& out, EncodeOptions opt, Summary summary) {
  opt.progress = progress;
  const auto t0 = std::chrono::steady_clock::now();
  tinygltf::Model model;
  GltfReadResult rr = read_gltf(in, model);
  if (!rr.ok) return fail(rr.error);
  EncodeReport report;
  const Error encoded = encode_model(model, opt, report);
  progress_done();
  if (encoded.failed()) return fail(encoded, in + ": ");
  const std::string err = write_gltf(model, out);
  if (!err.empty()) return fail(err);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (summary == Summary::table) {
    print_encode_report(report, in, out, secs);
    // Every dB figure above is the encoder's own measure: say which.
    if (opt.quality_weight == QualityWeight::surface_area && !report.atlases.empty())
      std::printf("surface PSNR figures weigh each face by its 3D area (--quality-weight area)\n");
  }
  if (summary == Summary::json) std::printf("%s\n", encode_summary(report).dump().c_str());
  return 0;
}

const char* budget_name(DensityMode mode) {
  switch (mode) {
    case DensityMode::preserve_used_texels:
      return "used";
    case DensityMode::percentile:
      return "p90";
    case DensityMode::preserve_texel_count:
      break;
  }
  return "count";
}

// --texel-density as the options hold it: auto, Nx (a factor) or N.
std::string density_text(const EncodeOptions& o) {
  if (o.texel_density > 0) return CLI::detail::to_string(o.texel_density);
  if (o.texel_density_factor != 1.0) return CLI::detail::to_string(o.texel_density_factor) + "x";
  return "auto";
}

}  // namespace

// Every default comes from EncodeOptions (and DracoOptions): the options are
// bound to a default-constructed struct's fields and --help shows their
// values; the few options that are words stand for a field's value, and
// their defaults are read from the struct too.
Runner add_encode(CLI::App& app) {
  struct Args {
    std::vector<std::string> inputs;
    std::string out, geometry, partition, layout, orientation, texel_density, texel_budget, quality,
        quality_weight;
    EncodeOptions opt;
    BatchOptions batch;
    std::string shard, worker_in, worker_out;  // worker_*: one file of a batch, in a child (batch_encode.h)
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  a->geometry = a->opt.raw_geometry ? "raw" : "draco";
  a->partition = a->opt.greedy_partition ? "greedy" : "compact";
  a->layout = a->opt.mixed_layout ? "mixed" : "unfold";
  a->orientation = a->opt.orient_to_source ? "source" : "rectangle";
  a->texel_density = density_text(a->opt);
  a->texel_budget = budget_name(a->opt.texel_budget);
  app.option_defaults()->always_capture_default();
  app.add_option("inputs", a->inputs,
                 "Source .gltf or .glb; several files or directories (searched recursively) with --out-dir")
      ->required()
      ->check(CLI::ExistingPath);
  app.add_option("-o,--output", a->out, "Output file; .glb or .gltf decides the container");
  add_batch_options(app, a->batch, a->shard);
  app.add_option("--batch-worker-input", a->worker_in)->group("");
  app.add_option("--batch-worker-output", a->worker_out)->group("");
  app.add_option("--max-distortion", a->opt.tau,
                 "Distortion bound tau of every triangle (>= 1): each edge within tau of its 3D length, and "
                 "at least 1/tau^2 of its 3D area kept")
      ->check(CLI::Range(1.0001, 100.0));
  app.add_option("--partition", a->partition, "compact, or greedy (the paper's plain growth, a baseline)")
      ->check(CLI::IsMember({"compact", "greedy"}));
  app.add_option("--layout", a->layout,
                 "unfold (every patch replays the unfolding: format 1.0/1.1), or mixed (compact: also merge "
                 "patches whose union the solve method lays out within tau: format 1.4)")
      ->check(CLI::IsMember({"unfold", "mixed"}));
  app.add_option("--orientation", a->orientation,
                 "source (turn each patch so the source image's rows and columns run along the atlas's: "
                 "smaller images at equal quality on the corpus), or rectangle (its minimum-area rectangle "
                 "upright: the paper's rule, tighter packing)")
      ->check(CLI::IsMember({"source", "rectangle"}));
  app.add_flag(
      "--report-greedy", a->opt.report_greedy,
      "Also partition each primitive with plain greedy growth and report its patches, seams, fill and holes "
      "beside ours (not used for the output)");
  app.add_flag(
      "!--cross-source-seams", a->opt.keep_source_charts,
      "Let patches cross every source UV seam (fewer seams; the viewer then blends the two source regions "
      "along each crossed seam, which costs quality or texels). By default they cross only the seams the "
      "textures hide (the same colours on both sides)");
  app.add_flag("!--resample-all", a->opt.align_texels,
               "Resample every patch. By default a patch whose source map is a similarity (no stretch: a "
               "box face, a plane) and that keeps about its source's density lands on the source's texel "
               "grid and keeps its texels exactly, where the atlas is PNG");
  app.add_flag(
      "--least-squares-texels", a->opt.least_squares_texels,
      "Fit the atlas texels so that their bilinear reconstruction best matches the source over the "
      "surface (by default each texel samples the source at its centre; the fit costs bytes at equal "
      "quality on the corpus)");
  app.add_flag("!--keep-hidden-seams", a->opt.cross_hidden_seams,
               "Keep patches inside the source's UV charts even across seams the textures hide");
  app.add_option("--geometry", a->geometry, "draco, or raw (float accessors: isolates the UV part)")
      ->check(CLI::IsMember({"draco", "raw"}));
  app.add_option(
      "--texel-density", a->texel_density,
      "auto (keep the source's texels per unit), Nx (N times auto, e.g. 0.5x), or N texels per model unit");
  app.add_option(
         "--texel-budget", a->texel_budget,
         "what auto keeps: count (every source triangle's texels; repeated or mirrored UVs count per use), "
         "used (distinct source texels: smaller atlas, less detail), p90 (90th percentile density)")
      ->check(CLI::IsMember({"count", "used", "p90"}));
  app.add_option("--max-atlas-size", a->opt.max_atlas_size, "Largest atlas side in texels")
      ->check(CLI::Range(16, 65536));
  app.add_option(
         "--max-pages", a->opt.max_pages,
         "Atlas pages (images of --max-atlas-size) a texture set may spread over before its density shrinks "
         "to fit; a primitive too large for one page is cut into primitives of one page each. 1: one page")
      ->check(CLI::Range(1, 256));
  app.add_option("--gutter", a->opt.gutter, "Texels of padding around every patch")->check(CLI::Range(0, 64));
  app.add_flag(
      "--power-of-two", a->opt.power_of_two,
      "Atlas sides as powers of two (default: multiples of 16, so that MIP levels 0-4 halve exactly)");
  app.add_option("--image-format", a->opt.image_format,
                 "keep, png, jpeg or webp (lossy; the file then requires EXT_texture_webp)")
      ->check(CLI::IsMember({"keep", "png", "jpeg", "webp"}));
  app.add_option("--image-quality,--jpeg-quality", a->opt.image_quality,
                 "JPEG or WebP quality of warped images (1-100); 0 matches the source JPEG's (else 90)")
      ->check(CLI::Range(0, 100));
  app.add_option(
         "--min-psnr", a->opt.min_psnr,
         "Quality floor in dB (surface PSNR of each warped atlas against its source). Below it the density "
         "goes up 1.5x, then 2x; still below, the primitives keep explicit UVs. Default: 38 with auto "
         "density, off when --texel-density is given; 0: off")
      ->check(CLI::Range(0.0, 99.0));
  CLI::Option* target =
      app.add_option("--target-psnr,--goal-psnr", a->opt.goal_psnr,
                     "Quality in dB the density aims at (surface PSNR of each atlas against its "
                     "sources): below it the density goes up 1.5x, then 2x, and texels are never "
                     "halved below it. With a lossy coder (JPEG or WebP) and no --image-quality, "
                     "the encoder also chooses the coder's quality: the one whose atlas reaches "
                     "the target with the fewest bytes, or a lossless (PNG) atlas where that reaches "
                     "it in fewer. Default: 44 (near transparency) with PNG "
                     "atlases, where an atlas that then outweighs its sources keeps explicit UVs; "
                     "with JPEG atlases 40, bounding only the halving. 0: trade quality for bytes "
                     "down to --min-psnr")
          ->check(CLI::Range(-1.0, 99.0));
  app.add_option("--quality", a->quality,
                 "A target as a word: high (44 dB, near transparency), medium (40 dB) or low (38 dB, the "
                 "floor); the same as that --target-psnr")
      ->check(CLI::IsMember({"high", "medium", "low"}))
      ->excludes(target);
  app.add_option(
         "--quality-weight", a->quality_weight,
         "What the floor and the target weigh: texel (each source texel alike, so a face counts by its "
         "UV area) or area (each face by its 3D area, as `compare --weight area`: where the source "
         "puts many texels on little surface, such as a polar map's pole, fewer atlas texels follow)")
      ->default_val("texel")
      ->check(CLI::IsMember({"texel", "area"}));
  app.add_flag(
      "!--fixed-density", a->opt.adaptive_density,
      "Keep every patch at its measured density (default: patches whose content is smooth have their "
      "texels halved, up to six times, while the atlas keeps --min-psnr plus 0.5 dB)");
  app.add_flag("!--always-implicit", a->opt.quality_fallback,
               "Never fall back to explicit UVs, for quality or for size (still raise the density to meet "
               "--min-psnr)");
  app.add_flag(
      "!--no-texel-reuse", a->opt.texel_reuse,
      "Warp every patch's own texels, even where the source shows the same texels on several "
      "(mirrored or repeated) parts; by default those parts share one place in the atlas (format 1.3)");
  app.add_flag("!--explicit-uvs", a->opt.implicit_uvs,
               "Keep TEXCOORD_0 explicit (plain Draco for everything)");
  app.add_option("--position-bits", a->opt.draco.position_bits, "Draco position quantization")
      ->check(CLI::Range(1, 30));
  app.add_option("--normal-bits", a->opt.draco.normal_bits, "Draco normal quantization")
      ->check(CLI::Range(1, 30));
  app.add_option("--color-bits", a->opt.draco.color_bits, "Draco colour quantization")
      ->check(CLI::Range(1, 30));
  app.add_option("--texcoord-bits", a->opt.draco.texcoord_bits, "Draco texcoord quantization (other sets)")
      ->check(CLI::Range(1, 30));
  app.add_option("--generic-bits", a->opt.draco.generic_bits, "Draco generic attribute quantization")
      ->check(CLI::Range(1, 30));
  app.add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  return [a]() {
    EncodeOptions opt = a->opt;
    opt.raw_geometry = a->geometry == "raw";
    opt.greedy_partition = a->partition == "greedy";
    opt.mixed_layout = a->layout == "mixed";
    opt.orient_to_source = a->orientation == "source";
    if (a->quality_weight == "area") opt.quality_weight = QualityWeight::surface_area;
    if (!a->quality.empty()) opt.goal_psnr = a->quality == "high" ? 44 : a->quality == "medium" ? 40 : 38;
    opt.texel_budget = a->texel_budget == "used"  ? DensityMode::preserve_used_texels
                       : a->texel_budget == "p90" ? DensityMode::percentile
                                                  : DensityMode::preserve_texel_count;
    if (a->texel_density != density_text(EncodeOptions{})) {
      const bool relative = !a->texel_density.empty() && a->texel_density.back() == 'x';
      double value = 0;
      try {
        size_t used = 0;
        value = std::stod(a->texel_density, &used);
        if (used != a->texel_density.size() - (relative ? 1 : 0)) throw std::invalid_argument("trailing");
      } catch (...) {
        return fail("--texel-density takes 'auto', 'Nx' or a positive number, not '" + a->texel_density + "'",
                    2);
      }
      if (!(value > 0) || !std::isfinite(value)) return fail("--texel-density must be positive", 2);
      if (relative)
        opt.texel_density_factor = value;
      else
        opt.texel_density = value;
    }
    if (!a->worker_in.empty()) return encode_file(a->worker_in, a->worker_out, opt, Summary::json);
    if (!a->batch.out_dir.empty()) {
      if (!a->out.empty()) return fail("-o names one output; --out-dir mirrors the inputs' paths", 2);
      if (!a->shard.empty())
        if (std::string e = parse_shard(a->shard, a->batch.shard); !e.empty()) return fail(e, 2);
      a->batch.inputs = a->inputs;
      a->batch.quiet = a->quiet;
      std::vector<std::string> worker = {self_executable()};
      for (const auto& arg : invocation_arguments()) worker.push_back(arg);
      return run_batch_encode(a->batch, worker);
    }
    if (a->inputs.size() != 1 || !std::filesystem::is_regular_file(a->inputs[0]))
      return fail("several inputs, or a directory, need --out-dir DIR", 2);
    if (a->out.empty()) return fail("give the output file: -o OUTPUT (or --out-dir DIR)", 2);
    return encode_file(a->inputs[0], a->out, opt, a->quiet ? Summary::none : Summary::table);
  };
}

}  // namespace gltfwarp::cli
