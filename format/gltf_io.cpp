// glTF container I/O on top of tinygltf (Debian's header, compiled once in
// third_party_glue/tinygltf_impl.cpp).
#include "format/gltf_io.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

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
std::string write_atomically(const std::string& path, const std::string& bytes) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  fs::path tmp = target;
  tmp += ".tmp-gltf-warp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return "cannot write " + path;
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
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
      if (!v.IsNumber()) continue;
      int idx = v.GetNumberAsInt();
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
        if (bv == obj.end() || !bv->second.IsNumber()) continue;
        int idx = bv->second.GetNumberAsInt();
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
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return false;
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
      if (obj[kHiddenIndices].IsNumber()) prim.indices = obj[kHiddenIndices].GetNumberAsInt();
      obj.erase(kHiddenIndices);
      it->second = tinygltf::Value(obj);
    }
}

uint32_t read_u32(const std::string& b, size_t at) {
  return static_cast<uint32_t>(static_cast<uint8_t>(b[at])) | static_cast<uint32_t>(static_cast<uint8_t>(b[at + 1])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(b[at + 2])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(b[at + 3])) << 24;
}

void put_u32(std::string& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

}  // namespace

GltfReadResult read_gltf(const std::string& path, tinygltf::Model& model) {
  GltfReadResult r;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    r.error = "cannot open " + path;
    return r;
  }
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) {
    r.error = "cannot read " + path + ": the file is empty";
    return r;
  }
  const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
  std::string base_dir = std::filesystem::path(path).parent_path().string();
  if (base_dir.empty()) base_dir = ".";

  // Park Draco index accessors (see park_draco_indices), rebuilding the GLB
  // container around the patched JSON when needed.
  if (binary && bytes.size() >= 20) {
    const uint32_t json_len = read_u32(bytes, 12);
    if (read_u32(bytes, 16) == 0x4E4F534Au && json_len <= bytes.size() - 20) {
      std::string json = bytes.substr(20, json_len);
      if (park_draco_indices(json)) {
        while (json.size() % 4) json.push_back(' ');
        const std::string rest = bytes.substr(20 + json_len);
        std::string glb = "glTF";
        put_u32(glb, 2);
        put_u32(glb, static_cast<uint32_t>(12 + 8 + json.size() + rest.size()));
        put_u32(glb, static_cast<uint32_t>(json.size()));
        put_u32(glb, 0x4E4F534Au);
        glb += json;
        glb += rest;
        bytes.swap(glb);
      }
    }
  } else if (!binary) {
    park_draco_indices(bytes);
  }

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_image_bytes, nullptr);
  std::string err, warn;
  bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                                 static_cast<unsigned int>(bytes.size()), base_dir)
                   : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                static_cast<unsigned int>(bytes.size()), base_dir);
  r.warning = one_line(warn);
  if (!ok) {
    r.error = "cannot read " + path + ": " + one_line(err.empty() ? "malformed glTF" : err);
    return r;
  }
  restore_draco_indices(model);
  for (auto& img : model.images) {
    if (img.mimeType.empty()) img.mimeType = mime_for_bytes(img.image, {});
  }
  r.ok = true;
  return r;
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
    if (!acc_refs[i] && std::find(replaced.begin(), replaced.end(), static_cast<int>(i)) != replaced.end()) continue;
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
  for (size_t i = 0; i < model.bufferViews.size(); ++i) {
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
  tinygltf::TinyGLTF writer;
  std::ostringstream os;
  if (binary) {
    for (auto& b : model.buffers) b.uri.clear();
    if (!writer.WriteGltfSceneToStream(&model, os, false, true)) return "cannot serialise " + path;
    return write_atomically(path, os.str());
  }
  // JSON: serialise without the buffer bytes, then point buffer 0 at a .bin
  // file beside the .gltf (a data URI would cost a third more bytes).
  namespace fs = std::filesystem;
  std::vector<unsigned char> bin;
  if (!model.buffers.empty()) bin.swap(model.buffers[0].data);
  if (!writer.WriteGltfSceneToStream(&model, os, true, false)) return "cannot serialise " + path;
  if (!model.buffers.empty()) bin.swap(model.buffers[0].data);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(os.str());
  } catch (const std::exception& e) {
    return std::string("cannot serialise ") + path + ": " + e.what();
  }
  if (!model.buffers.empty()) {
    const std::string bin_name = fs::path(path).stem().string() + ".bin";
    auto& b = doc["buffers"][0];
    b.erase("uri");
    b["uri"] = bin_name;
    b["byteLength"] = model.buffers[0].data.size();
    const fs::path bin_path = fs::path(path).parent_path() / bin_name;
    std::string err = write_atomically(bin_path.string(), std::string(model.buffers[0].data.begin(),
                                                                      model.buffers[0].data.end()));
    if (!err.empty()) return err;
  }
  return write_atomically(path, doc.dump(2) + "\n");
}

}  // namespace gltfwarp
