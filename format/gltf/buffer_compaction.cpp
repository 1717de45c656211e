// Buffer compaction (format/gltf/buffer_compaction.h).
#include "format/gltf/buffer_compaction.h"

#include <functional>
#include <map>
#include <set>

#include "format/gltf/gltf_accessors.h"

namespace gltfwarp {
namespace {

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

std::string mime_for_bytes(const std::vector<unsigned char>& b, const std::string& fallback) {
  if (b.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  if (b.size() >= 12 && b[0] == 'R' && b[1] == 'I' && b[2] == 'F' && b[3] == 'F' && b[8] == 'W' &&
      b[9] == 'E' && b[10] == 'B' && b[11] == 'P')
    return "image/webp";
  if (b.size() >= 12 && b[0] == 0xAB && b[1] == 'K' && b[2] == 'T' && b[3] == 'X') return "image/ktx2";
  return fallback.empty() ? "application/octet-stream" : fallback;
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

}  // namespace gltfwarp
