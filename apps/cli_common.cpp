// What both halves of the CLI share (sources in commands.h).
#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <exception>

#include "apps/commands.h"

namespace gltfwarp::cli {

int fail(const std::string& message, int code) {
  std::string line = message;
  for (auto& c : line)
    if (c == '\n') c = ' ';
  std::fprintf(stderr, "gltf-warp: %s\n", line.c_str());
  return code;
}

void progress(const std::string& stage, double fraction) {
  if (!isatty(2)) return;
  std::fprintf(stderr, "\r%-10s %3d%%", stage.c_str(), static_cast<int>(fraction * 100));
  std::fflush(stderr);
}

void progress_done() {
  if (isatty(2)) std::fprintf(stderr, "\r%-16s\r", "");
}

namespace {
std::vector<std::string>& arguments() {
  static std::vector<std::string> args;  // set once, by run_verbs, before any verb runs
  return args;
}
}  // namespace

const std::vector<std::string>& invocation_arguments() { return arguments(); }

int run_verbs(CLI::App& app, const std::vector<Verb>& verbs, int argc, char** argv) {
  arguments().assign(argv + std::min(argc, 1), argv + argc);
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("gltf-warp 0.1.0"));
  std::map<CLI::App*, Runner> runners;
  for (const Verb& v : verbs) {
    CLI::App* sub = app.add_subcommand(v.name, v.help);
    if (v.add) runners[sub] = v.add(*sub);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(e.what(), 2);
  }
  try {
    for (auto* sub : app.get_subcommands())
      if (auto it = runners.find(sub); it != runners.end()) return it->second();
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what(), 3);
  }
  return fail("this verb is not available here", 2);
}

const std::vector<Verb>& all_verbs() {
  static const std::vector<Verb> verbs = {
      {"encode", "Encode: drop TEXCOORD_0, write Draco geometry, the UV bitstream and warped textures",
       nullptr},
      {"decode", "Decode: rebuild TEXCOORD_0 and write a standard glTF 2.0 file", nullptr},
      {"info", "Per-primitive sizes, patches and bitstream sections of a glTF file", nullptr},
      {"sample", "Write a generated textured sample model (.glb or .gltf)", nullptr},
      {"compare", "Surface colour PSNR between a scene and its decoded round trip", nullptr},
  };
  return verbs;
}

}  // namespace gltfwarp::cli
