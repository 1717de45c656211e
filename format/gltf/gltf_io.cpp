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

#include "format/gltf/buffer_compaction.h"
#include "format/gltf/glb_container.h"
#include "format/gltf/gltf_accessors.h"
#include "format/gltf/gltf_prevalidate.h"

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

}  // namespace

namespace {

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
