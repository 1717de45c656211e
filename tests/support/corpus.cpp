#include "support/corpus.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace gltfwarp::test {

bool on_ci() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

std::string corpus_dir() {
  if (const char* env = std::getenv("GLTFWARP_CORPUS"))
    if (fs::is_directory(env)) return env;
  const fs::path p = fs::path(GLTFWARP_SOURCE_DIR) / ".." / "shared" / "corpus";
  return fs::is_directory(p) ? fs::canonical(p).string() : std::string();
}

std::vector<CorpusModel> corpus_models() {
  std::vector<CorpusModel> out;
  const std::string dir = corpus_dir();
  if (dir.empty()) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const auto ext = e.path().extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    const auto rel = fs::relative(e.path(), dir);
    std::string name = rel.begin()->string();
    if (ext == ".glb") name += "-glb";
    out.push_back({name, e.path().string()});
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return out;
}

std::string corpus_path(const std::string& name) {
  for (const auto& m : corpus_models())
    if (m.name == name) return m.path;
  return {};
}

int run_command(const std::string& cmd, std::string* out) {
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf;
  std::string text;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) text.append(buf.data(), n);
  const int status = pclose(pipe);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string scratch_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("gltf-warp-tests-" + std::to_string(getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

ValidatorResult validate(const std::string& path) {
  ValidatorResult r;
  const fs::path script = fs::path(GLTFWARP_SOURCE_DIR) / "tools" / "validate.mjs";
  const fs::path pkg = fs::path(GLTFWARP_SOURCE_DIR) / "tools" / "node_modules" / "gltf-validator";
  if (!fs::exists(pkg)) return r;
  std::string out;
  run_command("node '" + script.string() + "' '" + path + "' 2>&1", &out);
  r.raw = out;
  const auto e = out.find("\"errors\":");
  if (e == std::string::npos) return r;
  r.ran = true;
  r.errors = std::atoi(out.c_str() + e + 9);
  const auto c = out.find("\"codes\":");
  if (c != std::string::npos) r.codes_json = out.substr(c + 8, out.rfind('}') - c - 8);
  return r;
}

}  // namespace gltfwarp::test
