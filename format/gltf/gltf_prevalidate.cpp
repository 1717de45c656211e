// Pre-validation of a glTF document (format/gltf/gltf_prevalidate.h).
#include "format/gltf/gltf_prevalidate.h"

#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

namespace gltfwarp {
namespace {

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

}  // namespace

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

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

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

}  // namespace gltfwarp
