// The batch options of `gltf-warp encode` (apps/batch_encode.h), registered
// here so that cmd_encode.cpp keeps only the encoder's own.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "apps/batch_encode.h"

namespace gltfwarp::cli {

// `shard` receives --shard's text (parse_shard checks it when the batch runs).
void add_batch_options(CLI::App& app, BatchOptions& batch, std::string& shard);

}  // namespace gltfwarp::cli
