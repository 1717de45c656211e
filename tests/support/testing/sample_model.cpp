#include "tests/support/testing/sample_model.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "codec/decode/implicit_uv_primitive.h"
#include "codec/encode/texture/image_io.h"
#include "tests/support/testing/shapes.h"

namespace gltfwarp {
namespace {

// A texture with detail at every scale: a checkerboard, rings and a colour
// ramp, so that any resampling error shows in PSNR. The checker's edges are
// anti-aliased over about 5 texels, as a painted or photographed texture's
// are: a hard 0/1 step at every texel size is not something a resampler can
// keep, and no real texture has one.
std::vector<uint8_t> procedural_texture(int n) {
  std::vector<uint8_t> px(static_cast<size_t>(n) * n * 3);
  const double pi = 3.14159265358979323846;
  const double sharpness = n / (2 * pi * 8 * 2.5);  // +-1 within 2.5 texels of a cell edge
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double u = (x + 0.5) / n, v = (y + 0.5) / n;
      const double sx = std::clamp(sharpness * std::sin(2 * pi * 8 * u), -1.0, 1.0);
      const double sy = std::clamp(sharpness * std::sin(2 * pi * 8 * v), -1.0, 1.0);
      const double check = 0.5 + 0.5 * sx * sy;  // 1 on light cells, 0 on dark ones
      const double ring = 0.5 + 0.5 * std::cos(40.0 * std::hypot(u - 0.5, v - 0.5));
      uint8_t* p = &px[(static_cast<size_t>(y) * n + x) * 3];
      p[0] = static_cast<uint8_t>(std::lround(255 * (0.25 + 0.6 * check) * (0.4 + 0.6 * u)));
      p[1] = static_cast<uint8_t>(std::lround(255 * (0.2 + 0.7 * ring * v)));
      p[2] = static_cast<uint8_t>(std::lround(255 * (0.9 - 0.6 * check) * (1.0 - 0.5 * u)));
    }
  return px;
}

ShapeMesh shape_by_name(const std::string& name, int faces, bool& ok) {
  ok = true;
  const int n = std::max(4, static_cast<int>(std::sqrt(faces / 2.0)));
  if (name == "twisted-cone") return make_twisted_cone(n, n);
  if (name == "torus") return make_torus(2 * n, n / 2 + 2);
  if (name == "twisted-loop") return make_twisted_loop(2 * n, n / 2 + 2);
  if (name == "sphere") return make_sphere(n, n / 2 + 2);
  if (name == "bumpy-sphere") return make_bumpy_sphere(n, n / 2 + 2);
  if (name == "cylinder") return make_cylinder_open(n, n / 2 + 1);
  if (name == "plane") return make_plane(n, n);
  ok = false;
  return {};
}

}  // namespace

std::vector<std::string> sample_model_names() {
  return {"twisted-cone", "torus", "twisted-loop", "sphere", "bumpy-sphere", "cylinder", "plane"};
}

std::string make_sample_model(const std::string& name, int faces, int texture_size, tinygltf::Model& model) {
  bool ok = false;
  const ShapeMesh shape = shape_by_name(name, faces, ok);
  if (!ok) return "unknown sample '" + name + "'";
  const TriMesh& m = shape.mesh;

  // Smooth normals: area-weighted face normals summed per vertex.
  std::vector<float> normals(m.positions.size(), 0.0f);
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const float* p[3];
    for (int k = 0; k < 3; ++k) p[k] = &m.positions[3 * m.indices[3 * f + k]];
    const float e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const float e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) normals[3 * m.indices[3 * f + k] + i] += n[i];
  }
  for (size_t v = 0; v < normals.size() / 3; ++v) {
    float* n = &normals[3 * v];
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0) {
      n[0] /= len;
      n[1] /= len;
      n[2] /= len;
    } else {
      n[2] = 1.0f;
    }
  }
  PrimitiveGeometry geom;
  geom.attributes.push_back(VertexAttribute::from_floats("POSITION", 3, m.positions));
  geom.attributes.push_back(VertexAttribute::from_floats("NORMAL", 3, normals));
  geom.triangles = m.indices;
  split_by_corner_uv(geom, shape.corner_uv);  // one vertex per (position, uv)

  std::vector<uint8_t> png;
  std::string err;
  const std::vector<uint8_t> pixels = procedural_texture(texture_size);
  OIIO::ImageBuf buf(OIIO::ImageSpec(texture_size, texture_size, 3, OIIO::TypeDesc::UINT8));
  buf.set_pixels(buf.roi(), OIIO::TypeDesc::UINT8, pixels.data());
  if (!encode_image(buf, "image/png", 0, png, err)) return err;

  model = tinygltf::Model();
  model.asset.version = "2.0";
  model.asset.generator = "gltf-warp sample";
  tinygltf::Primitive prim;
  for (const auto& a : geom.attributes)
    prim.attributes[a.semantic] = add_accessor(model, a, TINYGLTF_TARGET_ARRAY_BUFFER);
  prim.indices = add_index_accessor(model, geom.triangles, geom.vertex_count());
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = 0;
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = name;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  tinygltf::Image img;
  img.name = name + "-texture";
  img.mimeType = "image/png";
  img.image = std::move(png);
  img.as_is = true;
  model.images.push_back(std::move(img));
  tinygltf::Sampler s;
  s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  model.samplers.push_back(s);
  tinygltf::Texture tex;
  tex.source = 0;
  tex.sampler = 0;
  model.textures.push_back(tex);
  tinygltf::Material mat;
  mat.name = name + "-material";
  mat.pbrMetallicRoughness.baseColorTexture.index = 0;
  mat.pbrMetallicRoughness.metallicFactor = 0.0;
  model.materials.push_back(mat);
  return {};
}

}  // namespace gltfwarp
