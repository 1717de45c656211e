// glTF container I/O on top of tinygltf (Debian's header, compiled once in
// third_party_glue/tinygltf_impl.cpp).
#include "format/gltf/gltf_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include <nlohmann/json.hpp>

#include "format/gltf/gltf_accessors.h"

namespace gltfwarp {
namespace {

// Keep images as their encoded bytes: the codec decodes only the images it
// warps, and every other image must leave byte for byte as it came.
bool keep_image_bytes(tinygltf::Image* image, const int /*index*/, std::string* /*err*/,
                      std::string* /*warn*/, int /*req_width*/, int /*req_height*/,
                      const unsigned char* bytes, int size, void* /*user*/) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
  return tail == suffix;
}

std::string mime_for_bytes(const std::vector<unsigned char>& b, const std::string& fallback) {
  if (b.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  if (b.size() >= 12 && b[0] == 'R' && b[1] == 'I' && b[2] == 'F' && b[3] == 'F' && b[8] == 'W' &&
      b[9] == 'E' && b[10] == 'B' && b[11] == 'P')
    return "image/webp";
  if (b.size() >= 12 && b[0] == 0xAB && b[1] == 'K' && b[2] == 'T' && b[3] == 'X') return "image/ktx2";
  return fallback.empty() ? "application/octet-stream" : fallback;
}

// Writes bytes to a temporary file beside `path`, then renames it into place.
// Writes the concatenation of `parts` to path via a temporary file and a rename.
std::string write_atomically(const std::string& path, std::initializer_list<std::string_view> parts) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  fs::path tmp = target;
  tmp += ".tmp-gltf-warp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return "cannot write " + path;
    for (const std::string_view part : parts)
      out.write(part.data(), static_cast<std::streamsize>(part.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      return "cannot write " + path + " (disk full?)";
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return "cannot write " + path + ": " + ec.message();
  }
  return {};
}
std::string write_atomically(const std::string& path, const std::string& bytes) {
  return write_atomically(path, {std::string_view(bytes)});
}

void align4(std::vector<unsigned char>& data) {
  while (data.size() % 4) data.push_back(0);
}

// Every place the glTF 2.0 core (and the extensions we know) names an
// accessor or a bufferView, as mutable references, so renumbering is one loop.
template <typename Fn>
void for_each_accessor_ref(tinygltf::Model& m, Fn&& fn) {
  for (auto& mesh : m.meshes)
    for (auto& prim : mesh.primitives) {
      for (auto& [name, idx] : prim.attributes) fn(idx);
      fn(prim.indices);
      for (auto& target : prim.targets)
        for (auto& [name, idx] : target) fn(idx);
    }
  for (auto& anim : m.animations)
    for (auto& s : anim.samplers) {
      fn(s.input);
      fn(s.output);
    }
  for (auto& skin : m.skins) fn(skin.inverseBindMatrices);
  for (auto& node : m.nodes) {
    auto it = node.extensions.find("EXT_mesh_gpu_instancing");
    if (it == node.extensions.end() || !it->second.IsObject()) continue;
    auto obj = it->second.Get<tinygltf::Value::Object>();
    auto attrs = obj.find("attributes");
    if (attrs == obj.end() || !attrs->second.IsObject()) continue;
    auto attr_obj = attrs->second.Get<tinygltf::Value::Object>();
    for (auto& [name, v] : attr_obj) {
      int idx = value_index(v);
      if (idx < 0) continue;
      fn(idx);
      v = tinygltf::Value(idx);
    }
    attrs->second = tinygltf::Value(attr_obj);
    it->second = tinygltf::Value(obj);
  }
}

// bufferView references inside primitive extensions (Draco, ours).
void for_each_primitive_view_ref(tinygltf::Model& m, const std::function<void(int&)>& fn) {
  for (auto& mesh : m.meshes)
    for (auto& prim : mesh.primitives)
      for (auto& [name, ext] : prim.extensions) {
        if (!ext.IsObject()) continue;
        auto obj = ext.Get<tinygltf::Value::Object>();
        auto bv = obj.find("bufferView");
        if (bv == obj.end()) continue;
        int idx = value_index(bv->second);
        if (idx < 0) continue;
        fn(idx);
        bv->second = tinygltf::Value(idx);
        ext = tinygltf::Value(obj);
      }
}

template <typename Fn>
void for_each_view_ref(tinygltf::Model& m, Fn&& fn) {
  for (auto& a : m.accessors) {
    fn(a.bufferView);
    if (a.sparse.isSparse) {
      fn(a.sparse.indices.bufferView);
      fn(a.sparse.values.bufferView);
    }
  }
  for (auto& img : m.images) fn(img.bufferView);
  for_each_primitive_view_ref(m, fn);
}

}  // namespace

namespace {

constexpr const char* kHiddenIndices = "__gltf_warp_indices";

// tinygltf 2.7 rejects a primitive whose indices accessor has no bufferView,
// which is exactly how KHR_draco_mesh_compression declares it. Such indices
// are parked inside the Draco extension object while tinygltf parses, and put
// back afterwards (restore_draco_indices).
bool park_draco_indices(std::string& json_text) {
  nlohmann::json doc = nlohmann::json::parse(json_text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array())
    return false;
  bool changed = false;
  for (auto& mesh : doc["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (auto& prim : mesh["primitives"]) {
      if (!prim.is_object() || !prim.contains("indices") || !prim.contains("extensions")) continue;
      auto& exts = prim["extensions"];
      if (!exts.is_object() || !exts.contains("KHR_draco_mesh_compression") ||
          !exts["KHR_draco_mesh_compression"].is_object())
        continue;
      exts["KHR_draco_mesh_compression"][kHiddenIndices] = prim["indices"];
      prim.erase("indices");
      changed = true;
    }
  }
  if (changed) json_text = doc.dump();
  return changed;
}

void restore_draco_indices(tinygltf::Model& model) {
  for (auto& mesh : model.meshes)
    for (auto& prim : mesh.primitives) {
      auto it = prim.extensions.find("KHR_draco_mesh_compression");
      if (it == prim.extensions.end() || !it->second.IsObject() || !it->second.Has(kHiddenIndices)) continue;
      auto obj = it->second.Get<tinygltf::Value::Object>();
      prim.indices = value_index(obj[kHiddenIndices]);
      obj.erase(kHiddenIndices);
      it->second = tinygltf::Value(obj);
    }
}

void put_u32(std::string& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

}  // namespace

namespace {

constexpr uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534Au;
constexpr uint32_t kChunkBin = 0x004E4942u;

uint32_t load_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}

// True when arrays/objects nest deeper than `limit` (brackets outside
// strings). tinygltf turns extras and extensions into Values recursively and
// nlohmann serialises recursively: unbounded nesting would overflow the stack.
bool json_too_deep(const char* p, size_t n, size_t limit) {
  size_t depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < n; ++i) {
    const char c = p[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"')
      in_string = true;
    else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return false;
}

// The JSON and BIN chunks of a GLB, checked against the container's lengths
// (tinygltf 2.7 lets a BIN chunk's payload reach 8 bytes past the file).
struct GlbParts {
  std::string json;
  const uint8_t* bin = nullptr;
  size_t bin_size = 0;
};

std::string split_glb(const uint8_t* d, size_t n, GlbParts& out) {
  if (n < 12) return "truncated GLB header (" + std::to_string(n) + " bytes)";
  if (load_u32(d) != kGlbMagic) return "not a GLB file";
  const uint32_t version = load_u32(d + 4);
  if (version != 2) return "GLB version " + std::to_string(version) + " is not 2";
  const uint32_t length = load_u32(d + 8);
  if (length > n)
    return "truncated GLB: the header declares " + std::to_string(length) + " bytes, the file has " +
           std::to_string(n);
  if (length < 20) return "GLB has no JSON chunk";
  size_t off = 12;
  bool have_json = false, have_bin = false;
  while (off < length) {
    if (length - off < 8) return "truncated GLB chunk header at byte " + std::to_string(off);
    const uint32_t clen = load_u32(d + off), type = load_u32(d + off + 4);
    off += 8;
    if (clen > length - off)
      return "GLB chunk at byte " + std::to_string(off - 8) + " declares " + std::to_string(clen) +
             " bytes, past the end of the file";
    if (!have_json) {
      if (type != kChunkJson) return "the first GLB chunk is not JSON";
      if (clen == 0) return "the GLB JSON chunk is empty";
      out.json.assign(reinterpret_cast<const char*>(d + off), clen);
      have_json = true;
    } else if (type == kChunkBin && !have_bin) {
      out.bin = d + off;
      out.bin_size = clen;
      have_bin = true;
    }
    // Other chunk types are skipped, as the specification says.
    off += clen;
  }
  return {};
}

// A GLB tinygltf accepts: header, JSON padded with spaces, BIN (if any)
// padded with zeros, exact lengths. glb_head is everything before the BIN
// bytes, glb_tail the zeros after them.
std::string glb_head(std::string json, size_t bin_size) {
  while (json.size() % 4) json.push_back(' ');
  const size_t bin_padded = (bin_size + 3) / 4 * 4;
  std::string glb = "glTF";
  put_u32(glb, 2);
  put_u32(glb, static_cast<uint32_t>(12 + 8 + json.size() + (bin_size ? 8 + bin_padded : 0)));
  put_u32(glb, static_cast<uint32_t>(json.size()));
  put_u32(glb, kChunkJson);
  glb += json;
  if (bin_size) {
    put_u32(glb, static_cast<uint32_t>(bin_padded));
    put_u32(glb, kChunkBin);
  }
  return glb;
}
std::string_view glb_tail(size_t bin_size) { return std::string_view("\0\0\0", (4 - bin_size % 4) % 4); }
std::string make_glb(std::string json, const uint8_t* bin, size_t bin_size) {
  std::string glb = glb_head(std::move(json), bin_size);
  glb.append(reinterpret_cast<const char*>(bin), bin_size);
  glb += glb_tail(bin_size);
  return glb;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

// "http:", "https:", "file:", ...: an absolute URI we do not fetch.
bool has_uri_scheme(const std::string& uri) {
  const size_t colon = uri.find(':');
  if (colon == std::string::npos || colon < 2) return false;  // "C:" is a drive, not a scheme
  for (size_t i = 0; i < colon; ++i) {
    const char c = uri[i];
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.')) return false;
  }
  return std::isalpha(static_cast<unsigned char>(uri[0]));
}

bool is_absolute_path(const std::string& uri) {
  return !uri.empty() && (uri[0] == '/' || uri[0] == '\\' || (uri.size() > 1 && uri[1] == ':'));
}

std::optional<uint64_t> json_uint(const nlohmann::json& o, const char* key,
                                  std::optional<uint64_t> fallback) {
  if (!o.is_object()) return std::nullopt;
  auto it = o.find(key);
  if (it == o.end()) return fallback;
  if (!it->is_number_unsigned()) return std::nullopt;
  return it->get<uint64_t>();
}

// Checks tinygltf 2.7 does not do, on the parsed JSON before tinygltf sees it:
// every image's bufferView lies inside its buffer's declared byteLength
// (tinygltf hands the image loader a pointer and length without checking),
// and buffer/image URIs are data URIs or relative file names.
// Index-like members given as floats out of int's range ("texCoord": 1e30):
// tinygltf keeps them as doubles in extension Values, and GetNumberAsInt on
// them is undefined behaviour wherever they are read. Extras are user data
// and are not inspected. Depth is bounded by kMaxJsonDepth.
std::string find_bad_index(const nlohmann::json& j) {
  static const std::set<std::string> keys = {"index",  "texCoord",   "source",     "bufferView", "sampler",
                                             "buffer", "material",   "mesh",       "skin",       "camera",
                                             "node",   "indices",    "input",      "output",     "scene",
                                             "count",  "byteOffset", "byteLength", "byteStride"};
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "extras") continue;
      if (it->is_number_float() && keys.count(it.key())) {
        const double d = it->get<double>();
        if (!(d >= double(std::numeric_limits<int>::min()) && d <= double(std::numeric_limits<int>::max())) ||
            d != std::floor(d))
          return "'" + it.key() + "' is " + it->dump() + ", not an integer index";
      }
      if (std::string err = find_bad_index(*it); !err.empty()) return err;
    }
  } else if (j.is_array()) {
    for (const auto& e : j)
      if (std::string err = find_bad_index(e); !err.empty()) return err;
  }
  return {};
}

std::string prevalidate(const nlohmann::json& doc) {
  if (!doc.is_object()) return "the JSON root is not an object";
  if (std::string err = find_bad_index(doc); !err.empty()) return err;
  const auto arr = [&](const char* key) -> const nlohmann::json* {
    auto it = doc.find(key);
    return it != doc.end() && it->is_array() ? &*it : nullptr;
  };
  // Compressed buffer views hold no readable data until decompressed: say
  // so, rather than fail on the first byte count that does not add up.
  if (const nlohmann::json* required = arr("extensionsRequired"))
    for (const auto& name : *required)
      if (name == "EXT_meshopt_compression" || name == "KHR_meshopt_compression")
        return "it requires " + name.get<std::string>() +
               ", which gltf-warp cannot decompress (write it without meshopt compression first, "
               "e.g. gltfpack without -c)";
  const nlohmann::json* buffers = arr("buffers");
  const nlohmann::json* views = arr("bufferViews");
  if (buffers)
    for (size_t i = 0; i < buffers->size(); ++i) {
      const auto& b = (*buffers)[i];
      if (!b.is_object()) return "buffer " + std::to_string(i) + " is not an object";
      auto uri = b.find("uri");
      if (uri == b.end()) continue;
      if (!uri->is_string()) return "buffer " + std::to_string(i) + " has a uri that is not a string";
      const std::string u = uri->get<std::string>();
      if (is_data_uri(u)) continue;
      if (has_uri_scheme(u) || is_absolute_path(u))
        return "buffer " + std::to_string(i) + " uri '" + u + "' is not a relative file name";
    }
  // Primitives: tinygltf silently drops a primitive whose attributes are
  // not an object, and extension members that are not objects, which would
  // lose geometry or our UVs without a word. The two extensions the codec
  // owns must be well-formed objects naming existing bufferViews.
  const size_t view_count = views ? views->size() : 0;
  if (const nlohmann::json* meshes = arr("meshes"))
    for (size_t mi = 0; mi < meshes->size(); ++mi) {
      const auto& mesh = (*meshes)[mi];
      if (!mesh.is_object()) return "mesh " + std::to_string(mi) + " is not an object";
      auto prims = mesh.find("primitives");
      if (prims == mesh.end() || !prims->is_array())
        return "mesh " + std::to_string(mi) + " has no primitives array";
      for (size_t pi = 0; pi < prims->size(); ++pi) {
        const auto& prim = (*prims)[pi];
        const std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
        if (!prim.is_object()) return where + " is not an object";
        auto attrs = prim.find("attributes");
        if (attrs == prim.end() || !attrs->is_object()) return where + " has no attributes object";
        for (auto it = attrs->begin(); it != attrs->end(); ++it)
          if (!it->is_number_unsigned())
            return where + " attribute " + it.key() + " is not an accessor index";
        for (const char* key : {"indices", "material", "mode"})
          if (auto k = prim.find(key); k != prim.end() && !k->is_number_unsigned())
            return where + " " + key + " is not a non-negative integer";
        auto exts = prim.find("extensions");
        if (exts == prim.end() || !exts->is_object()) continue;
        for (const char* name : {"KHR_draco_mesh_compression", "GLTFWARP_implicit_texcoords"}) {
          auto e = exts->find(name);
          if (e == exts->end()) continue;
          const std::string what = where + " " + name;
          if (!e->is_object()) return what + " is not an object";
          auto bv = e->find("bufferView");
          if (bv == e->end() || !bv->is_number_unsigned() || bv->get<uint64_t>() >= view_count)
            return what + " does not name an existing bufferView";
          if (std::string(name) == "KHR_draco_mesh_compression") {
            auto da = e->find("attributes");
            if (da == e->end() || !da->is_object()) return what + " has no attributes object";
            for (auto it = da->begin(); it != da->end(); ++it)
              if (!it->is_number_unsigned() ||
                  it->get<uint64_t>() > uint64_t{std::numeric_limits<int>::max()})
                return what + " attribute " + it.key() + " is not a Draco attribute id";
          }
        }
      }
    }
  if (const nlohmann::json* images = arr("images"))
    for (size_t i = 0; i < images->size(); ++i) {
      const auto& img = (*images)[i];
      const std::string what = "image " + std::to_string(i);
      if (!img.is_object()) return what + " is not an object";
      if (auto uri = img.find("uri"); uri != img.end() && uri->is_string()) {
        const std::string u = uri->get<std::string>();
        if (is_absolute_path(u) && !has_uri_scheme(u)) return what + " uri '" + u + "' is an absolute path";
      }
      auto bv = img.find("bufferView");
      if (bv == img.end()) continue;
      if (!bv->is_number_unsigned() || !views || bv->get<uint64_t>() >= views->size())
        return what + " names a bufferView that does not exist";
      const auto& view = (*views)[bv->get<size_t>()];
      const auto buf = json_uint(view, "buffer", std::nullopt);
      const auto off = json_uint(view, "byteOffset", 0), len = json_uint(view, "byteLength", std::nullopt);
      if (!buf || !off || !len || !buffers || *buf >= buffers->size())
        return what + " names a malformed bufferView";
      const auto blen = json_uint((*buffers)[*buf], "byteLength", std::nullopt);
      if (!blen || *off > *blen || *len > *blen - *off)
        return what + " names a bufferView outside its buffer";
    }
  return {};
}

// Filesystem access for tinygltf: regular files only (never devices or
// FIFOs, which could hang or stream forever), bounded in size, and none at
// all when the caller forbids external files.
struct FsContext {
  bool allow = true;
};

bool fs_exists(const std::string& path, void* user) {
  if (!static_cast<FsContext*>(user)->allow) return false;
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string fs_expand(const std::string& path, void*) { return path; }

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!static_cast<FsContext*>(user)->allow || !fs::is_regular_file(path, ec)) {
    if (err) *err = "not a readable regular file";
    return false;
  }
  const auto size = fs::file_size(path, ec);
  if (ec || size > kMaxExternalFileBytes) {
    if (err) *err = ec ? ec.message() : "larger than " + std::to_string(kMaxExternalFileBytes) + " bytes";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(static_cast<size_t>(size));
  if (!in || (size && !in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size)))) {
    if (err) *err = "read error";
    return false;
  }
  return true;
}

bool fs_write_bytes(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
  return false;
}

// Keeps images as their encoded bytes (see keep_image_bytes) after checking
// that bytes embedded through a bufferView lie inside the loaded buffer.
bool keep_image_bytes_checked(tinygltf::Image* image, const int index, std::string* err, std::string* warn,
                              int req_width, int req_height, const unsigned char* bytes, int size,
                              void* user) {
  const auto* model = static_cast<const tinygltf::Model*>(user);
  if (size < 0) {
    if (err) *err += "image " + std::to_string(index) + " is too large\n";
    return false;
  }
  if (image->bufferView >= 0) {
    const auto& views = model->bufferViews;
    bool inside = false;
    if (static_cast<size_t>(image->bufferView) < views.size()) {
      const auto& v = views[image->bufferView];
      if (v.buffer >= 0 && static_cast<size_t>(v.buffer) < model->buffers.size()) {
        const auto& data = model->buffers[v.buffer].data;
        inside = v.byteOffset <= data.size() && v.byteLength <= data.size() - v.byteOffset &&
                 static_cast<size_t>(size) == v.byteLength;
      }
    }
    if (!inside) {
      if (err) *err += "image " + std::to_string(index) + " names a bufferView outside its buffer\n";
      return false;
    }
  }
  return keep_image_bytes(image, index, err, warn, req_width, req_height, bytes, size, nullptr);
}

}  // namespace

GltfReadResult read_gltf_memory(const uint8_t* data, size_t size, tinygltf::Model& model,
                                const GltfReadOptions& options) {
  GltfReadResult r;
  model = tinygltf::Model();
  const std::string& name = options.name;
  auto fail = [&](const std::string& why) {
    r.error = "cannot read " + name + ": " + one_line(why);
    return r;
  };
  if (size == 0) return fail("the file is empty");
  if (size > std::numeric_limits<uint32_t>::max()) return fail("files of 4 GiB or more are not supported");
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;

  GlbParts glb;
  if (binary) {
    std::string err = split_glb(data, size, glb);
    if (!err.empty()) return fail(err);
  } else {
    glb.json.assign(reinterpret_cast<const char*>(data), size);
  }
  if (json_too_deep(glb.json.data(), glb.json.size(), kMaxJsonDepth))
    return fail("the JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");

  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(glb.json);
  } catch (const std::exception& e) {
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0 && what.find("] ") != std::string::npos)
      what = what.substr(what.find("] ") + 2);
    return fail("malformed JSON: " + what);
  }
  if (std::string err = prevalidate(doc); !err.empty()) return fail(err);

  // Park Draco index accessors (see park_draco_indices); a GLB is always
  // rebuilt as a clean container around the (possibly patched) JSON.
  park_draco_indices(glb.json);
  std::string bytes = binary ? make_glb(std::move(glb.json), glb.bin, glb.bin_size) : std::move(glb.json);

  FsContext fs_ctx{options.allow_external_files};
  tinygltf::FsCallbacks fs{fs_exists, fs_expand, fs_read, fs_write_bytes, &fs_ctx};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(fs);
  loader.SetImageLoader(keep_image_bytes_checked, &model);
  std::string err, warn;
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                              reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<unsigned int>(bytes.size()), options.base_dir)
                : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                             static_cast<unsigned int>(bytes.size()), options.base_dir);
  } catch (const std::exception& e) {
    ok = false;
    err = e.what();
  }
  r.warning = one_line(warn);
  if (!ok) {
    model = tinygltf::Model();
    return fail(err.empty() ? "malformed glTF" : err);
  }
  restore_draco_indices(model);
  // Every bufferView inside its buffer: later stages copy views whole.
  for (size_t i = 0; i < model.bufferViews.size(); ++i) {
    const auto& v = model.bufferViews[i];
    const bool inside = v.buffer >= 0 && static_cast<size_t>(v.buffer) < model.buffers.size() &&
                        v.byteOffset <= model.buffers[v.buffer].data.size() &&
                        v.byteLength <= model.buffers[v.buffer].data.size() - v.byteOffset;
    if (!inside) {
      model = tinygltf::Model();
      return fail("bufferView " + std::to_string(i) + " lies outside its buffer");
    }
  }
  for (size_t i = 0; i < model.images.size(); ++i) {
    auto& img = model.images[i];
    // An image file that was named but not found is a missing input, not
    // something to pass through; absolute URIs (http: ...) are not fetched
    // and pass through as they are.
    if (img.image.empty() && img.bufferView < 0 && !img.uri.empty() && !is_data_uri(img.uri) &&
        !has_uri_scheme(img.uri)) {
      const std::string why = "image " + std::to_string(i) + " '" + img.uri + "' cannot be loaded" +
                              (options.allow_external_files ? "" : " (external files are not allowed here)");
      model = tinygltf::Model();  // img dangles from here on
      return fail(why);
    }
    if (img.mimeType.empty()) img.mimeType = mime_for_bytes(img.image, {});
  }
  r.ok = true;
  return r;
}

GltfReadResult read_gltf(const std::string& path, tinygltf::Model& model) {
  GltfReadResult r;
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    r.error = "cannot open " + path + ": no such file";
    return r;
  }
  if (!fs::is_regular_file(path, ec)) {
    r.error = "cannot read " + path + ": not a regular file";
    return r;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    r.error = "cannot open " + path;
    return r;
  }
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  GltfReadOptions options;
  options.name = path;
  options.base_dir = fs::path(path).parent_path().string();
  if (options.base_dir.empty()) options.base_dir = ".";
  return read_gltf_memory(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), model, options);
}

void compact_buffers(tinygltf::Model& model, const std::vector<int>& replaced) {
  // 1. Images that came from a URI (or were made by the codec) move into views.
  //    Their bytes are appended to the old buffer 0 first so that step 2 sees
  //    one uniform set of views.
  if (model.buffers.empty()) model.buffers.emplace_back();
  for (auto& img : model.images) {
    if (img.bufferView >= 0 || img.image.empty()) continue;
    auto& buf = model.buffers[0].data;
    align4(buf);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buf.size();
    view.byteLength = img.image.size();
    buf.insert(buf.end(), img.image.begin(), img.image.end());
    model.bufferViews.push_back(view);
    img.bufferView = static_cast<int>(model.bufferViews.size() - 1);
    img.mimeType = mime_for_bytes(img.image, img.mimeType);
    img.uri.clear();
    img.image.clear();
    img.as_is = false;
  }
  for (auto& img : model.images) {
    if (img.bufferView >= 0) {
      img.uri.clear();
      img.image.clear();
    }
  }

  // 2. Drop accessors nothing references any more, then bufferViews.
  std::vector<int> acc_refs(model.accessors.size(), 0);
  for_each_accessor_ref(model, [&](int& i) {
    if (i >= 0 && static_cast<size_t>(i) < acc_refs.size()) acc_refs[i]++;
  });
  std::vector<int> acc_map(model.accessors.size(), -1);
  std::vector<tinygltf::Accessor> kept_acc;
  for (size_t i = 0; i < model.accessors.size(); ++i) {
    if (!acc_refs[i] && model.accessors[i].bufferView < 0 && !model.accessors[i].sparse.isSparse) {
      // Unreferenced and empty: nothing could need it.
      continue;
    }
    if (!acc_refs[i] && std::find(replaced.begin(), replaced.end(), static_cast<int>(i)) != replaced.end())
      continue;
    acc_map[i] = static_cast<int>(kept_acc.size());
    kept_acc.push_back(std::move(model.accessors[i]));
  }
  model.accessors = std::move(kept_acc);
  for_each_accessor_ref(model, [&](int& i) {
    if (i >= 0 && static_cast<size_t>(i) < acc_map.size()) i = acc_map[i];
  });

  std::vector<int> view_refs(model.bufferViews.size(), 0);
  for_each_view_ref(model, [&](int& i) {
    if (i >= 0 && static_cast<size_t>(i) < view_refs.size()) view_refs[i]++;
  });

  // 3. Rebuild one buffer from the referenced views, in their order.
  tinygltf::Buffer out;
  if (!model.buffers.empty()) {
    out.name = model.buffers[0].name;
    out.extras = model.buffers[0].extras;
    out.extensions = model.buffers[0].extensions;
  }
  std::vector<int> view_map(model.bufferViews.size(), -1);
  std::vector<tinygltf::BufferView> kept_views;
  // When every referenced view lies in buffer 0, in ascending order and
  // without overlap, and none would move up, the rebuild can slide them down
  // inside buffer 0 (front to back, so nothing is overwritten before it is
  // read) and zero the alignment gaps: the same bytes as copying into a new
  // buffer, without a second copy of everything (the decoder's buffer holds
  // the whole decoded geometry).
  size_t total = 0, old_end = 0;
  bool in_place = model.buffers.size() == 1;
  for (size_t i = 0; i < model.bufferViews.size() && in_place; ++i) {
    if (!view_refs[i]) continue;
    const tinygltf::BufferView& v = model.bufferViews[i];
    const size_t size = model.buffers[0].data.size();
    total = (total + 3) / 4 * 4;
    in_place = v.buffer == 0 && v.byteOffset <= size && v.byteLength <= size - v.byteOffset &&
               v.byteOffset >= old_end && total <= v.byteOffset;
    old_end = v.byteOffset + v.byteLength;
    total += v.byteLength;
  }
  if (in_place) {
    out.data = std::move(model.buffers[0].data);
    size_t end = 0;
    for (size_t i = 0; i < model.bufferViews.size(); ++i) {
      if (!view_refs[i]) continue;
      tinygltf::BufferView v = model.bufferViews[i];
      const size_t offset = (end + 3) / 4 * 4;
      std::fill(out.data.begin() + static_cast<std::ptrdiff_t>(end),
                out.data.begin() + static_cast<std::ptrdiff_t>(offset), 0);
      if (offset != v.byteOffset && v.byteLength)
        std::memmove(out.data.data() + offset, out.data.data() + v.byteOffset, v.byteLength);
      v.buffer = 0;
      v.byteOffset = offset;
      end = offset + v.byteLength;
      view_map[i] = static_cast<int>(kept_views.size());
      kept_views.push_back(v);
    }
    out.data.resize(end);
  } else {
    size_t reserve = 0;
    for (size_t i = 0; i < model.bufferViews.size(); ++i)
      if (view_refs[i]) reserve += model.bufferViews[i].byteLength + 3;
    out.data.reserve(reserve);
  }
  for (size_t i = 0; i < model.bufferViews.size() && !in_place; ++i) {
    if (!view_refs[i]) continue;
    tinygltf::BufferView v = model.bufferViews[i];
    const bool valid_source = v.buffer >= 0 && static_cast<size_t>(v.buffer) < model.buffers.size() &&
                              v.byteOffset + v.byteLength <= model.buffers[v.buffer].data.size();
    // Vertex data wants its natural alignment; 4 is enough for all glTF types.
    align4(out.data);
    const size_t offset = out.data.size();
    if (valid_source) {
      const auto& src = model.buffers[v.buffer].data;
      out.data.insert(out.data.end(), src.begin() + static_cast<std::ptrdiff_t>(v.byteOffset),
                      src.begin() + static_cast<std::ptrdiff_t>(v.byteOffset + v.byteLength));
    } else {
      out.data.resize(out.data.size() + v.byteLength, 0);
    }
    v.buffer = 0;
    v.byteOffset = offset;
    view_map[i] = static_cast<int>(kept_views.size());
    kept_views.push_back(v);
  }
  model.bufferViews = std::move(kept_views);
  for_each_view_ref(model, [&](int& i) {
    if (i >= 0 && static_cast<size_t>(i) < view_map.size()) i = view_map[i];
  });
  model.buffers.clear();
  if (!out.data.empty()) {
    align4(out.data);
    model.buffers.push_back(std::move(out));
  }
}

std::string write_gltf(tinygltf::Model& model, const std::string& path) {
  compact_buffers(model);
  const bool binary = ends_with(path, ".glb");
  namespace fs = std::filesystem;
  // Serialise the JSON without the buffer bytes, then fix it up with
  // nlohmann: tinygltf 2.7 writes an object whose members are all defaults
  // (e.g. a texture with no source) as null, which no reader accepts.
  tinygltf::TinyGLTF writer;
  std::ostringstream os;
  std::vector<unsigned char> bin;
  if (!model.buffers.empty()) bin.swap(model.buffers[0].data);
  for (auto& b : model.buffers) b.uri.clear();
  // tinygltf casts the min/max of integer accessors to int, undefined past
  // int's range (UNSIGNED_INT, or a hostile input's 1e30): we write those.
  std::vector<std::pair<std::vector<double>, std::vector<double>>> int_bounds(model.accessors.size());
  for (size_t i = 0; i < model.accessors.size(); ++i) {
    auto& a = model.accessors[i];
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) continue;
    int_bounds[i] = {std::move(a.minValues), std::move(a.maxValues)};
    a.minValues.clear();
    a.maxValues.clear();
  }
  const bool serialised = writer.WriteGltfSceneToStream(&model, os, !binary, false);
  for (size_t i = 0; i < model.accessors.size(); ++i) {
    if (model.accessors[i].componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) continue;
    model.accessors[i].minValues = std::move(int_bounds[i].first);
    model.accessors[i].maxValues = std::move(int_bounds[i].second);
  }
  if (!model.buffers.empty()) bin.swap(model.buffers[0].data);
  if (!serialised) return "cannot serialise " + path;
  nlohmann::json doc;
  std::string json_text;
  try {
    doc = nlohmann::json::parse(os.str());
    for (auto it = doc.begin(); it != doc.end(); ++it) {
      if (!it->is_array()) continue;
      for (auto& element : *it)
        if (element.is_null()) element = nlohmann::json::object();
    }
    for (size_t i = 0; i < model.accessors.size(); ++i) {
      const auto& a = model.accessors[i];
      if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || !doc.contains("accessors")) continue;
      auto bounds = [](const std::vector<double>& v) {
        nlohmann::json out = nlohmann::json::array();
        for (double d : v) {
          if (!std::isfinite(d)) return nlohmann::json();
          if (d == std::floor(d) && std::fabs(d) < 9e15)
            out.push_back(static_cast<int64_t>(d));
          else
            out.push_back(d);
        }
        return out;
      };
      const nlohmann::json lo = bounds(a.minValues), hi = bounds(a.maxValues);
      if (!a.minValues.empty() && !lo.is_null()) doc["accessors"][i]["min"] = lo;
      if (!a.maxValues.empty() && !hi.is_null()) doc["accessors"][i]["max"] = hi;
    }
    if (!model.buffers.empty()) {
      auto& b = doc["buffers"][0];
      b.erase("uri");
      if (!binary) b["uri"] = fs::path(path).stem().string() + ".bin";
      b["byteLength"] = model.buffers[0].data.size();
    }
    json_text = binary ? doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)
                       : doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  } catch (const std::exception& e) {
    return std::string("cannot serialise ") + path + ": " + one_line(e.what());
  }
  if (binary) {
    const auto& data = model.buffers.empty() ? bin : model.buffers[0].data;
    // The BIN bytes go to the file straight from the buffer, not through a copy.
    return write_atomically(path, {glb_head(std::move(json_text), data.size()),
                                   std::string_view(reinterpret_cast<const char*>(data.data()), data.size()),
                                   glb_tail(data.size())});
  }
  // JSON: buffer 0 goes to a .bin file beside the .gltf (a data URI would
  // cost a third more bytes).
  if (!model.buffers.empty()) {
    const fs::path bin_path = fs::path(path).parent_path() / (fs::path(path).stem().string() + ".bin");
    const auto& data = model.buffers[0].data;
    std::string err = write_atomically(
        bin_path.string(), {std::string_view(reinterpret_cast<const char*>(data.data()), data.size())});
    if (!err.empty()) return err;
  }
  return write_atomically(path, json_text);
}

}  // namespace gltfwarp
