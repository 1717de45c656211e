// `gltf-warp encode A.glb B.gltf DIR... --out-dir OUT`: encodes a library.
//
// Each file is encoded by a child process (this executable again, in its
// hidden one-file worker mode), --jobs at a time, from a pool of threads
// that each wait on one child. Why children, not N encodes in one process:
//  - a crash (or an out-of-memory kill) on one hostile or huge file ends
//    that file's child only; the batch reports it and goes on;
//  - each child's memory (about 1.7 GB at peak for a 1M-triangle model with
//    4096² textures) goes back to the system when it exits, so the peak is
//    that of the --jobs largest files at once, with no fragmentation growth
//    over thousands of files;
//  - the encoder itself is reentrant (each warp makes its own OpenImageIO
//    TextureSystem and temp file; no mutable statics but an atomic counter),
//    but tinygltf, stb and Draco are not ours to audit on every upgrade.
// The cost is one process start per file (0.2 s: loading OpenImageIO).
//
// Resume: a file whose output (and the output's .bin) is newer than the
// input (and the input's .bin and images) is skipped unless --force. The
// same options give byte-identical outputs, whatever --jobs.
#pragma once

#include <string>
#include <vector>

#include "apps/input_list.h"

namespace gltfwarp::cli {

struct BatchOptions {
  std::vector<std::string> inputs;  // files and directories (walked recursively)
  std::string out_dir;              // outputs mirror each input's path below its argument
  std::string container = "keep";   // keep (the input's extension) | glb | gltf
  int jobs = 0;                     // files encoded at once; 0: default_jobs()
  std::string report_path;          // JSON lines, one per file of this shard; "": none
  Shard shard;                      // this machine's share of the sorted list
  bool force = false;               // encode even when the output is current
  bool quiet = false;               // no per-file lines for files that went well
};

// The cores, but no more than the available memory / 1.8 GB (the peak of a
// 1M-triangle encode, about 1.7 GB, with a margin), and at least 1.
int default_jobs();

// Runs the batch; `worker` is the command line of one child without its
// file pair (the executable and this run's own arguments), to which
// `--batch-worker-input IN --batch-worker-output OUT` is appended.
// Returns 0 when no file failed, 1 otherwise (2: bad arguments).
int run_batch_encode(const BatchOptions& options, const std::vector<std::string>& worker);

}  // namespace gltfwarp::cli
