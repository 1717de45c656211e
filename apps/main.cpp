// gltf-warp: encode glTF scenes without explicit texture coordinates.
//
// This executable runs decode and info; the imaging verbs run in the module
// it loads for them (commands.h says why).
#include <dlfcn.h>
#include <unistd.h>

#include <cstring>
#include <string>

#include "apps/commands.h"

namespace {

using gltfwarp::cli::fail;

// The directory of this executable ("" if unknown).
std::string exe_dir() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return {};
  std::string path(buf, size_t(n));
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash);
}

// Beside the executable (the build tree), else in the installed library directory.
int run_imaging_module(int argc, char** argv) {
  const std::string dir = exe_dir();
  const std::string beside = dir + "/libgltf-warp-imaging.so";
  const std::string installed = dir + "/../" GLTFWARP_INSTALL_LIBDIR "/libgltf-warp-imaging.so";
  const std::string path = access(beside.c_str(), R_OK) == 0 ? beside : installed;
  void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!module) {
    const char* why = dlerror();
    return fail("cannot load the imaging module (" + path + "): " + (why ? why : "unknown error"));
  }
  using Entry = int (*)(int, char**);
  auto entry = reinterpret_cast<Entry>(dlsym(module, "gltfwarp_imaging_main"));
  if (!entry) return fail("the imaging module " + path + " has no entry point");
  return entry(argc, argv);  // the module stays loaded until exit
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gltfwarp::cli;
  for (const char* verb : {"encode", "sample", "compare"})
    if (argc >= 2 && std::strcmp(argv[1], verb) == 0) return run_imaging_module(argc, argv);
  std::vector<Verb> verbs = all_verbs();
  for (Verb& v : verbs) {
    if (std::strcmp(v.name, "decode") == 0) v.add = add_decode;
    if (std::strcmp(v.name, "info") == 0) v.add = add_info;
  }
  CLI::App app{"gltf-warp: glTF 2.0 codec that stores textured meshes without explicit texture coordinates"};
  return run_verbs(app, verbs, argc, argv);
}
