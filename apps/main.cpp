// gltf-warp: encode glTF scenes without explicit texture coordinates.
#include <cstdio>
#include <exception>
#include <map>
#include <unistd.h>

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

}  // namespace gltfwarp::cli

int main(int argc, char** argv) {
  using namespace gltfwarp::cli;
  CLI::App app{"gltf-warp: glTF 2.0 codec that stores textured meshes without explicit texture coordinates"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("gltf-warp 0.1.0"));
  std::map<CLI::App*, Runner> runners;
  auto add = [&](const char* name, const char* help, Runner (*fn)(CLI::App&)) {
    CLI::App* sub = app.add_subcommand(name, help);
    runners[sub] = fn(*sub);
  };
  add("encode", "Encode: drop TEXCOORD_0, write Draco geometry, the UV bitstream and warped textures", add_encode);
  add("decode", "Decode: rebuild TEXCOORD_0 and write a standard glTF 2.0 file", add_decode);
  add("info", "Per-primitive sizes, patches and bitstream sections of a glTF file", add_info);
  add("sample", "Write a generated textured sample model (.glb or .gltf)", add_sample);
  add("compare", "Surface colour PSNR between a scene and its decoded round trip", add_compare);
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
    for (auto* sub : app.get_subcommands()) return runners.at(sub)();
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what(), 3);
  }
  return 0;
}
