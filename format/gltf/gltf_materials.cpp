#include "format/gltf/gltf_materials.h"

#include "format/gltf/gltf_accessors.h"
#include "format/gltf/gltf_primitive.h"

#include <algorithm>
#include <cmath>

namespace gltfwarp {
namespace {

constexpr const char* kTransform = "KHR_texture_transform";
constexpr const char* kWebp = "EXT_texture_webp";

void read_transform(const tinygltf::ExtensionMap& exts, TextureSlot& s) {
  auto it = exts.find(kTransform);
  if (it == exts.end() || !it->second.IsObject()) return;
  const auto& t = it->second;
  double ox = 0, oy = 0, rot = 0, sx = 1, sy = 1;
  auto num = [](const tinygltf::Value& v, double def) { return v.IsNumber() ? v.GetNumberAsDouble() : def; };
  if (t.Has("offset") && t.Get("offset").IsArray() && t.Get("offset").ArrayLen() == 2) {
    ox = num(t.Get("offset").Get(0), 0);
    oy = num(t.Get("offset").Get(1), 0);
  }
  if (t.Has("rotation")) rot = num(t.Get("rotation"), 0);
  if (t.Has("scale") && t.Get("scale").IsArray() && t.Get("scale").ArrayLen() == 2) {
    sx = num(t.Get("scale").Get(0), 1);
    sy = num(t.Get("scale").Get(1), 1);
  }
  if (t.Has("texCoord") && t.Get("texCoord").IsNumber()) s.tex_coord = value_index(t.Get("texCoord"));
  const double c = std::cos(rot), si = std::sin(rot);
  // Translation * Rotation * Scale, as the extension's README defines it.
  s.transform = {c * sx, si * sy, ox, -si * sx, c * sy, oy};
  s.has_transform = true;
}

void add_core(std::vector<TextureSlot>& out, int material, const char* key, int index, int tex_coord,
              const tinygltf::ExtensionMap& exts, ColorSpace cs, bool normal) {
  if (index < 0) return;
  TextureSlot s;
  s.material = material;
  s.key = key;
  s.texture = index;
  s.tex_coord = tex_coord;
  s.color_space = cs;
  s.normal_map = normal;
  read_transform(exts, s);
  out.push_back(s);
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Slots of material extensions that hold colour (sRGB) rather than data.
bool is_srgb_extension_slot(const std::string& key) {
  return key == "sheenColorTexture" || key == "specularColorTexture" || key == "diffuseTexture" ||
         key == "specularGlossinessTexture";
}

}  // namespace

namespace {

constexpr const char* kVariants = "KHR_materials_variants";

// The mappings array of the primitive's KHR_materials_variants, or null.
const tinygltf::Value* variant_mappings(const tinygltf::Primitive& prim) {
  const auto it = prim.extensions.find(kVariants);
  if (it == prim.extensions.end() || !it->second.IsObject() || !it->second.Has("mappings")) return nullptr;
  const tinygltf::Value& mappings = it->second.Get("mappings");
  return mappings.IsArray() ? &mappings : nullptr;
}

}  // namespace

std::vector<int> primitive_materials(const tinygltf::Primitive& prim) {
  std::vector<int> out;
  auto add = [&](int m) {
    if (m >= 0 && std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  };
  add(prim.material);
  if (const tinygltf::Value* mappings = variant_mappings(prim))
    for (size_t i = 0; i < mappings->ArrayLen(); ++i) {
      const tinygltf::Value& m = mappings->Get(int(i));
      if (m.IsObject() && m.Has("material") && m.Get("material").IsNumber())
        add(value_index(m.Get("material")));
    }
  return out;
}

void replace_primitive_material(tinygltf::Primitive& prim, int from, int to) {
  if (prim.material == from) prim.material = to;
  if (!variant_mappings(prim)) return;
  auto& mappings =
      prim.extensions[kVariants].Get<tinygltf::Value::Object>()["mappings"].Get<tinygltf::Value::Array>();
  for (tinygltf::Value& m : mappings) {
    if (!m.IsObject() || !m.Has("material") || !m.Get("material").IsNumber() ||
        value_index(m.Get("material")) != from)
      continue;
    m.Get<tinygltf::Value::Object>()["material"] = tinygltf::Value(to);
  }
}

int texture_image(const tinygltf::Model& model, int texture) {
  if (texture < 0 || static_cast<size_t>(texture) >= model.textures.size()) return -1;
  const tinygltf::Texture& t = model.textures[texture];
  int src = t.source;
  if (src < 0)
    if (auto it = t.extensions.find(kWebp); it != t.extensions.end() && it->second.IsObject() &&
                                            it->second.Has("source") && it->second.Get("source").IsInt())
      src = it->second.Get("source").GetNumberAsInt();
  if (src < 0 || static_cast<size_t>(src) >= model.images.size()) return -1;
  return src;
}

void set_texture_image(tinygltf::Model& model, int texture, int image) {
  tinygltf::Texture& t = model.textures[size_t(texture)];
  if (model.images[size_t(image)].mimeType == "image/webp") {
    t.source = -1;
    tinygltf::Value::Object ext;
    ext["source"] = tinygltf::Value(image);
    t.extensions[kWebp] = tinygltf::Value(ext);
    declare_extension(model, kWebp, true);
  } else {
    t.source = image;
    t.extensions.erase(kWebp);
  }
}

void point_textures_at_image(tinygltf::Model& model, int image) {
  for (size_t t = 0; t < model.textures.size(); ++t)
    if (texture_image(model, int(t)) == image) set_texture_image(model, int(t), image);
}

void replace_image_bytes(tinygltf::Model& model, int image, std::vector<unsigned char> bytes,
                         const std::string& mime) {
  tinygltf::Image& img = model.images[size_t(image)];
  img.image = std::move(bytes);
  img.mimeType = mime;
  img.bufferView = -1;
  img.uri.clear();
  img.as_is = false;
  point_textures_at_image(model, image);
}

void texture_wraps(const tinygltf::Model& model, int texture, int& wrap_s, int& wrap_t) {
  wrap_s = wrap_t = TINYGLTF_TEXTURE_WRAP_REPEAT;
  if (texture < 0 || static_cast<size_t>(texture) >= model.textures.size()) return;
  const int sampler = model.textures[texture].sampler;
  if (sampler < 0 || static_cast<size_t>(sampler) >= model.samplers.size()) return;
  wrap_s = model.samplers[sampler].wrapS;
  wrap_t = model.samplers[sampler].wrapT;
}

std::vector<TextureSlot> texture_slots(const tinygltf::Model& model, int material) {
  std::vector<TextureSlot> out;
  if (material < 0 || static_cast<size_t>(material) >= model.materials.size()) return out;
  const auto& m = model.materials[material];
  const auto& pbr = m.pbrMetallicRoughness;
  add_core(out, material, "baseColorTexture", pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
           pbr.baseColorTexture.extensions, ColorSpace::srgb, false);
  add_core(out, material, "metallicRoughnessTexture", pbr.metallicRoughnessTexture.index,
           pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions, ColorSpace::linear,
           false);
  add_core(out, material, "normalTexture", m.normalTexture.index, m.normalTexture.texCoord,
           m.normalTexture.extensions, ColorSpace::linear, true);
  add_core(out, material, "occlusionTexture", m.occlusionTexture.index, m.occlusionTexture.texCoord,
           m.occlusionTexture.extensions, ColorSpace::linear, false);
  add_core(out, material, "emissiveTexture", m.emissiveTexture.index, m.emissiveTexture.texCoord,
           m.emissiveTexture.extensions, ColorSpace::srgb, false);
  for (const auto& [ext_name, ext] : m.extensions) {
    if (!ext.IsObject()) continue;
    for (const auto& key : ext.Keys()) {
      const auto& v = ext.Get(key);
      if (!ends_with(key, "Texture") || !v.IsObject() || !v.Has("index") || !v.Get("index").IsNumber())
        continue;
      TextureSlot s;
      s.material = material;
      s.extension = ext_name;
      s.key = key;
      s.texture = value_index(v.Get("index"));
      s.tex_coord = v.Has("texCoord") && v.Get("texCoord").IsNumber() ? value_index(v.Get("texCoord")) : 0;
      s.color_space = is_srgb_extension_slot(key) ? ColorSpace::srgb : ColorSpace::linear;
      s.normal_map = ends_with(key, "NormalTexture");
      if (v.Has("extensions") && v.Get("extensions").IsObject()) {
        tinygltf::ExtensionMap em;
        for (const auto& ek : v.Get("extensions").Keys()) em[ek] = v.Get("extensions").Get(ek);
        read_transform(em, s);
      }
      out.push_back(s);
    }
  }
  return out;
}

void retarget_slot(tinygltf::Model& model, const TextureSlot& slot, int texture) {
  auto& m = model.materials[slot.material];
  auto fix = [&](auto& info) {
    info.index = texture;
    info.texCoord = 0;
    info.extensions.erase(kTransform);
  };
  if (slot.extension.empty()) {
    if (slot.key == "baseColorTexture") fix(m.pbrMetallicRoughness.baseColorTexture);
    if (slot.key == "metallicRoughnessTexture") fix(m.pbrMetallicRoughness.metallicRoughnessTexture);
    if (slot.key == "normalTexture") fix(m.normalTexture);
    if (slot.key == "occlusionTexture") fix(m.occlusionTexture);
    if (slot.key == "emissiveTexture") fix(m.emissiveTexture);
    return;
  }
  auto it = m.extensions.find(slot.extension);
  if (it == m.extensions.end() || !it->second.IsObject()) return;
  auto obj = it->second.Get<tinygltf::Value::Object>();
  auto sit = obj.find(slot.key);
  if (sit == obj.end() || !sit->second.IsObject()) return;
  auto info = sit->second.Get<tinygltf::Value::Object>();
  info["index"] = tinygltf::Value(texture);
  info.erase("texCoord");
  auto e = info.find("extensions");
  if (e != info.end() && e->second.IsObject()) {
    auto eo = e->second.Get<tinygltf::Value::Object>();
    eo.erase(kTransform);
    if (eo.empty())
      info.erase(e);
    else
      e->second = tinygltf::Value(eo);
  }
  sit->second = tinygltf::Value(info);
  it->second = tinygltf::Value(obj);
}

}  // namespace gltfwarp

namespace gltfwarp {
namespace {

// Calls fn on every texture index a material slot holds (core and extension slots).
template <typename Fn>
void for_each_texture_ref(tinygltf::Model& model, Fn&& fn) {
  for (auto& m : model.materials) {
    fn(m.pbrMetallicRoughness.baseColorTexture.index);
    fn(m.pbrMetallicRoughness.metallicRoughnessTexture.index);
    fn(m.normalTexture.index);
    fn(m.occlusionTexture.index);
    fn(m.emissiveTexture.index);
    for (auto& [name, ext] : m.extensions) {
      if (!ext.IsObject()) continue;
      auto obj = ext.template Get<tinygltf::Value::Object>();
      bool changed = false;
      for (auto& [key, v] : obj) {
        if (key.size() < 7 || key.compare(key.size() - 7, 7, "Texture") != 0 || !v.IsObject()) continue;
        auto info = v.template Get<tinygltf::Value::Object>();
        auto it = info.find("index");
        if (it == info.end() || !it->second.IsNumber()) continue;
        int idx = value_index(it->second);
        fn(idx);
        it->second = tinygltf::Value(idx);
        v = tinygltf::Value(info);
        changed = true;
      }
      if (changed) ext = tinygltf::Value(obj);
    }
  }
}

// Calls fn on every image index a texture names (source and extension sources).
template <typename Fn>
void for_each_image_ref(tinygltf::Model& model, Fn&& fn) {
  for (auto& t : model.textures) {
    fn(t.source);
    for (auto& [name, ext] : t.extensions) {
      if (!ext.IsObject() || !ext.Has("source") || !ext.Get("source").IsNumber()) continue;
      auto obj = ext.template Get<tinygltf::Value::Object>();
      int idx = value_index(obj["source"]);
      fn(idx);
      obj["source"] = tinygltf::Value(idx);
      ext = tinygltf::Value(obj);
    }
  }
}

template <typename T, typename Refs>
void drop_unreferenced(std::vector<T>& items, const std::vector<int>& candidates, Refs&& refs) {
  std::vector<int> count(items.size(), 0);
  refs([&](int& i) {
    if (i >= 0 && static_cast<size_t>(i) < count.size()) count[i]++;
  });
  std::vector<int> map(items.size(), -1);
  std::vector<T> kept;
  for (size_t i = 0; i < items.size(); ++i) {
    const bool candidate =
        std::find(candidates.begin(), candidates.end(), static_cast<int>(i)) != candidates.end();
    if (candidate && count[i] == 0) continue;
    map[i] = static_cast<int>(kept.size());
    kept.push_back(std::move(items[i]));
  }
  items = std::move(kept);
  refs([&](int& i) {
    if (i >= 0 && static_cast<size_t>(i) < map.size()) i = map[i];
  });
}

}  // namespace

void drop_unused_textures(tinygltf::Model& model, const std::vector<int>& candidates) {
  std::vector<int> images;
  for (int t : candidates) {
    if (t < 0 || static_cast<size_t>(t) >= model.textures.size()) continue;
    if (model.textures[t].source >= 0) images.push_back(model.textures[t].source);
    for (const auto& [name, ext] : model.textures[t].extensions)
      if (ext.IsObject() && ext.Has("source") && ext.Get("source").IsNumber())
        images.push_back(value_index(ext.Get("source")));
  }
  drop_unreferenced(model.textures, candidates, [&](auto&& fn) { for_each_texture_ref(model, fn); });
  drop_unreferenced(model.images, images, [&](auto&& fn) { for_each_image_ref(model, fn); });
}

}  // namespace gltfwarp
