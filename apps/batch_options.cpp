#include "apps/batch_options.h"

namespace gltfwarp::cli {

void add_batch_options(CLI::App& app, BatchOptions& batch, std::string& shard) {
  const char* group = "Batch (several inputs or directories, with --out-dir)";
  app.add_option("--out-dir", batch.out_dir,
                 "Encode every input into DIR, at its path below its directory argument (a file argument: "
                 "its name); a run that finds an output newer than its input skips it")
      ->type_name("DIR")
      ->group(group);
  app.add_option("--container", batch.container,
                 "Outputs' container: keep (the input's: .gltf writes .gltf + .bin), glb or gltf")
      ->default_val("keep")
      ->check(CLI::IsMember({"keep", "glb", "gltf"}))
      ->group(group);
  app.add_option("-j,--jobs", batch.jobs,
                 "Files encoded at once, each in its own process. Memory grows with it: a 1M-triangle model "
                 "with 4096² textures peaks at 1.7 GB per job. Default: the cores, at most available "
                 "memory / 1.8 GB; at most 64")
      ->type_name("N")
      ->check(CLI::Range(1, 64))
      ->group(group);
  app.add_option("--report", batch.report_path,
                 "Write a JSON line per file: input, output, status (ok, skipped, error), bytes_in, "
                 "bytes_out, seconds, psnr_db, handling, error")
      ->type_name("FILE")
      ->group(group);
  app.add_option("--shard", shard,
                 "i/n: encode only the files at index i, i+n, i+2n, ... of the sorted input list (0 <= i < "
                 "n), for array jobs across machines")
      ->type_name("I/N")
      ->group(group);
  app.add_flag("--force", batch.force, "Encode even the files whose output is newer than their input")
      ->group(group);
}

}  // namespace gltfwarp::cli
