// The gltf-warp command-line verbs. Each registers its CLI11 subcommand and
// returns the function that runs it (exit code).
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace gltfwarp::cli {

using Runner = std::function<int()>;

Runner add_encode(CLI::App& app);
Runner add_decode(CLI::App& app);
Runner add_info(CLI::App& app);
Runner add_sample(CLI::App& app);
Runner add_compare(CLI::App& app);

// One line on stderr, "gltf-warp: <message>"; returns the exit code to use.
int fail(const std::string& message, int code = 1);

// Progress on stderr, only when it is a terminal.
void progress(const std::string& stage, double fraction);
void progress_done();

}  // namespace gltfwarp::cli
