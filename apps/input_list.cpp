#include "apps/input_list.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

namespace gltfwarp::cli {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool is_gltf_name(const fs::path& p) {
  const std::string ext = lower(p.extension().string());
  return ext == ".gltf" || ext == ".glb";
}

// Whether `p` is `dir` or below it (both made absolute and normal).
bool is_within(const fs::path& p, const fs::path& dir) {
  if (dir.empty()) return false;
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(p, ec), d = fs::weakly_canonical(dir, ec);
  auto [dir_end, _] = std::mismatch(d.begin(), d.end(), a.begin(), a.end());
  return dir_end == d.end();
}

// A relative file reference of a .gltf (buffer or image URI): not a data:
// URI, no scheme, not absolute. Percent-escapes are decoded (glTF URIs are
// RFC 3986; "my%20texture.png" names "my texture.png").
bool local_uri(const std::string& uri, std::string& path) {
  if (uri.empty() || uri.rfind("data:", 0) == 0 || uri.find("://") != std::string::npos || uri[0] == '/')
    return false;
  path.clear();
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size()) {
      int v = 0;
      if (std::from_chars(uri.data() + i + 1, uri.data() + i + 3, v, 16).ptr == uri.data() + i + 3) {
        path += char(v);
        i += 2;
        continue;
      }
    }
    path += uri[i];
  }
  return true;
}

}  // namespace

InputList list_inputs(const std::vector<std::string>& arguments, const std::string& exclude) {
  InputList list;
  for (const std::string& arg : arguments) {
    std::error_code ec;
    if (fs::is_regular_file(arg, ec)) {
      list.items.push_back({arg, fs::path(arg).filename().string()});
      continue;
    }
    if (!fs::is_directory(arg, ec)) {
      list.error = arg + ": neither a file nor a directory";
      return list;
    }
    std::vector<BatchInput> found;
    fs::recursive_directory_iterator it(arg, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
      const fs::path& p = it->path();
      const bool hidden = p.filename().string().rfind('.', 0) == 0;
      if (it->is_directory(ec) && (hidden || is_within(p, exclude))) {
        it.disable_recursion_pending();
        continue;
      }
      if (hidden || !is_gltf_name(p) || !it->is_regular_file(ec)) continue;
      found.push_back({p.string(), fs::relative(p, arg, ec).generic_string()});
    }
    if (ec) {
      list.error = arg + ": " + ec.message();
      return list;
    }
    std::sort(found.begin(), found.end(),
              [](const BatchInput& a, const BatchInput& b) { return a.relative < b.relative; });
    list.items.insert(list.items.end(), found.begin(), found.end());
  }
  return list;
}

std::string parse_shard(const std::string& text, Shard& shard) {
  const std::string usage = "--shard takes i/n with 0 <= i < n (e.g. 0/4), not '" + text + "'";
  const size_t slash = text.find('/');
  if (slash == std::string::npos) return usage;
  const char* b = text.data();
  const char* e = b + text.size();
  uint32_t i = 0, n = 0;
  auto r1 = std::from_chars(b, b + slash, i);
  auto r2 = std::from_chars(b + slash + 1, e, n);
  if (slash == 0 || r1.ptr != b + slash || r1.ec != std::errc() || r2.ptr != e || r2.ec != std::errc() ||
      n == 0 || i >= n)
    return usage;
  shard = {i, n};
  return {};
}

std::vector<size_t> shard_indices(size_t size, Shard shard) {
  std::vector<size_t> mine;
  for (size_t k = shard.index; k < size; k += shard.count) mine.push_back(k);
  return mine;
}

std::string output_path(const BatchInput& item, const std::string& out_dir, const std::string& container) {
  fs::path rel(item.relative);
  if (container != "keep") rel.replace_extension("." + container);
  return (fs::path(out_dir) / rel).string();
}

std::vector<fs::path> files_of(const std::string& gltf_path) {
  std::vector<fs::path> files = {gltf_path};
  if (lower(fs::path(gltf_path).extension().string()) != ".gltf") return files;
  std::ifstream in(gltf_path, std::ios::binary);
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object()) return files;
  const fs::path dir = fs::path(gltf_path).parent_path();
  for (const char* key : {"buffers", "images"}) {
    auto list = doc.find(key);
    if (list == doc.end() || !list->is_array()) continue;
    for (const auto& entry : *list) {
      std::string path;
      if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string() ||
          !local_uri(entry["uri"].get<std::string>(), path))
        continue;
      std::error_code ec;
      if (fs::is_regular_file(dir / path, ec) &&
          std::find(files.begin(), files.end(), dir / path) == files.end())
        files.push_back(dir / path);
    }
  }
  return files;
}

uint64_t total_bytes(const std::vector<fs::path>& files) {
  uint64_t sum = 0;
  for (const auto& f : files) {
    std::error_code ec;
    const auto n = fs::file_size(f, ec);
    if (!ec) sum += n;
  }
  return sum;
}

bool output_is_current(const std::string& input, const std::string& output) {
  std::error_code ec;
  if (!fs::is_regular_file(output, ec)) return false;
  fs::file_time_type newest_in = fs::file_time_type::min();
  for (const auto& f : files_of(input)) {
    const auto t = fs::last_write_time(f, ec);
    if (ec) return false;
    newest_in = std::max(newest_in, t);
  }
  for (const auto& f : files_of(output)) {
    const auto t = fs::last_write_time(f, ec);
    if (ec || !(t > newest_in)) return false;
  }
  return true;
}

}  // namespace gltfwarp::cli
