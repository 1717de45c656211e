// The gltf-warp command-line verbs. Each registers its CLI11 subcommand and
// returns the function that runs it (exit code).
//
// The CLI comes in two halves. The gltf-warp executable runs decode and info
// itself; encode, sample and compare, which warp and code images, run in the
// module libgltf-warp-imaging.so that it loads for them (imaging_module.h).
// OpenImageIO pulls in about 250 shared libraries whose loading took 0.19 s
// of every run, a fifth of decoding a million triangles.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace gltfwarp::cli {

using Runner = std::function<int()>;

Runner add_encode(CLI::App& app);
Runner add_decode(CLI::App& app);
Runner add_info(CLI::App& app);
Runner add_sample(CLI::App& app);
Runner add_compare(CLI::App& app);

struct Verb {
  const char* name;
  const char* help;
  Runner (*add)(CLI::App&);  // nullptr: listed (for --help) but run elsewhere
};

// The five verbs with their one-line help, in --help order (add unset).
const std::vector<Verb>& all_verbs();

// Registers `verbs` on `app`, parses argv and runs the chosen one; help,
// version and parse errors as CLI11 reports them (parse errors exit 2).
int run_verbs(CLI::App& app, const std::vector<Verb>& verbs, int argc, char** argv);

// This run's arguments after the executable's name, as run_verbs received them.
const std::vector<std::string>& invocation_arguments();

// One line on stderr, "gltf-warp: <message>"; returns the exit code to use.
int fail(const std::string& message, int code = 1);

// Progress on stderr, only when it is a terminal.
void progress(const std::string& stage, double fraction);
void progress_done();

}  // namespace gltfwarp::cli
