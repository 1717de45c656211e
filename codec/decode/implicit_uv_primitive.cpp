#include "codec/decode/implicit_uv_primitive.h"

#include <cmath>
#include <cstring>

#include "codec/decode/embedding_mesh.h"
#include "codec/decode/tangents.h"
#include "format/bitstream/decode_uvs.h"

namespace gltfwarp {

namespace {

// TANGENT (xyz, w) per vertex from the rebuilt UVs, MikkTSpace convention.
VertexAttribute tangent_attribute(const PrimitiveGeometry& geom) {
  return VertexAttribute::from_floats(
      "TANGENT", 4,
      vertex_tangents(geom.find("POSITION")->to_floats(), geom.find("NORMAL")->to_floats(),
                      geom.find("TEXCOORD_0")->to_floats(), geom.triangles));
}

}  // namespace

void split_by_corner_uv(PrimitiveGeometry& geom, const std::vector<float>& corner_uv) {
  const size_t corners = geom.triangles.size();
  const size_t points = geom.vertex_count();
  // New vertices of each point as a chain: head[point] -> next[vertex] -> ...
  // A point's corners with bitwise-equal UVs share one new vertex; new
  // vertices are numbered in order of their first corner.
  std::vector<uint32_t> head(points, UINT32_MAX), next, origin;  // origin: new vertex -> point
  std::vector<float> uvs;
  next.reserve(points + points / 4);
  origin.reserve(points + points / 4);
  uvs.reserve(2 * (points + points / 4));
  for (size_t c = 0; c < corners; ++c) {
    const uint32_t p = geom.triangles[c];
    const float u = corner_uv[2 * c], v = corner_uv[2 * c + 1];
    uint32_t found = head[p];
    while (found != UINT32_MAX &&
           !(std::memcmp(&uvs[2 * found], &u, 4) == 0 && std::memcmp(&uvs[2 * found + 1], &v, 4) == 0))
      found = next[found];
    if (found == UINT32_MAX) {
      found = static_cast<uint32_t>(origin.size());
      origin.push_back(p);
      next.push_back(head[p]);
      head[p] = found;
      uvs.push_back(u);
      uvs.push_back(v);
    }
    geom.triangles[c] = found;
  }
  geom.erase("TEXCOORD_0");
  for (auto& a : geom.attributes) {
    const size_t es = a.element_size();
    std::vector<uint8_t> out(origin.size() * es);
    uint8_t* dst = out.data();
    const uint8_t* src = a.data.data();
    switch (es) {  // fixed sizes let the copy inline
      case 12:
        for (size_t i = 0; i < origin.size(); ++i)
          std::memcpy(dst + i * 12, src + size_t{origin[i]} * 12, 12);
        break;
      case 16:
        for (size_t i = 0; i < origin.size(); ++i)
          std::memcpy(dst + i * 16, src + size_t{origin[i]} * 16, 16);
        break;
      default:
        for (size_t i = 0; i < origin.size(); ++i)
          std::memcpy(dst + i * es, src + size_t{origin[i]} * es, es);
    }
    a.data.swap(out);
  }
  geom.attributes.push_back(VertexAttribute::from_floats("TEXCOORD_0", 2, uvs));
}

std::string replay_input(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                         const PrimitiveGeometry& geom, ReplayInput& in) {
  const auto found = prim.extensions.find(ext::kName);
  if (found == prim.extensions.end()) return std::string("primitive has no ") + ext::kName;
  const auto& ext = found->second;
  if (!ext.IsObject() || !ext.Has("bufferView")) return std::string(ext::kName) + " object has no bufferView";
  if (std::string e = extension_view_bytes(model, ext, ext::kName, in.bitstream); !e.empty()) return e;
  const VertexAttribute* pos = geom.find("POSITION");
  if (!pos || pos->components != 3) return "primitive has no usable POSITION";
  // The encoder never lays out non-finite positions; the replay must not see them.
  if (pos->component_type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    for (size_t i = 0; i < pos->data.size(); i += 4) {
      uint32_t bits;
      std::memcpy(&bits, pos->data.data() + i, 4);
      if ((bits & 0x7F800000u) == 0x7F800000u) return "POSITION holds a NaN or infinite value";
    }
  } else {
    for (size_t e = 0; e < pos->count(); ++e)
      for (int i = 0; i < 3; ++i)
        if (!std::isfinite(pos->get(e, i))) return "POSITION holds a NaN or infinite value";
  }
  in.position = pos;
  return {};
}

std::string rebuild_texcoords(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                              PrimitiveGeometry& geom) {
  ReplayInput in;
  if (std::string err = replay_input(model, prim, geom, in); !err.empty()) return err;
  std::vector<uint32_t> point_to_vertex;
  const TriMesh mesh = embedding_mesh(*in.position, geom.triangles, point_to_vertex);
  std::vector<float> corner_uv;
  const UvStatus st = decode_uvs(mesh, in.bitstream, corner_uv);
  if (st != UvStatus::ok) return std::string("bad UV bitstream: ") + to_string(st);
  if (corner_uv.size() != geom.triangles.size() * 2) return "bad UV bitstream: wrong number of corner UVs";

  split_by_corner_uv(geom, corner_uv);
  const auto& ext = prim.extensions.at(ext::kName);  // replay_input found it an object
  const bool tangents =
      ext.Has("tangents") && ext.Get("tangents").IsBool() && ext.Get("tangents").Get<bool>();
  const VertexAttribute* normal = geom.find("NORMAL");
  if (tangents && normal && normal->components == 3) {
    geom.erase("TANGENT");
    geom.attributes.push_back(tangent_attribute(geom));
  }
  return {};
}

}  // namespace gltfwarp
