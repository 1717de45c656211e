#include "support/malformed.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include <sys/stat.h>

#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "format/gltf/gltf_accessors.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"
#include "tests/support/testing/sample_model.h"

namespace gltfwarp::test {

// ---------------------------------------------------------------- meshes

MeshSpec grid_mesh(int nx, int ny, float ox, float oy) {
  MeshSpec m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const float u = float(i) / float(nx), v = float(j) / float(ny);
      m.positions.insert(m.positions.end(), {ox + u, oy + v, 0.15f * std::sin(3 * u) * std::cos(2 * v)});
      m.uvs.insert(m.uvs.end(), {u, v});
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

MeshSpec strip_mesh(int nx) {
  MeshSpec g = grid_mesh(nx, 1);
  MeshSpec m;
  m.positions = g.positions;
  m.uvs = g.uvs;
  m.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
  for (int i = 0; i <= nx; ++i) m.indices.insert(m.indices.end(), {uint32_t(i), uint32_t(i + nx + 1)});
  return m;
}

MeshSpec fan_mesh(int n) {
  MeshSpec m;
  m.mode = TINYGLTF_MODE_TRIANGLE_FAN;
  m.positions = {0, 0, 0.6f};
  m.uvs = {0.5f, 0.5f};
  for (int i = 0; i < n; ++i) {
    const float a = 2.0f * 3.14159265f * float(i) / float(n);
    m.positions.insert(m.positions.end(), {std::cos(a), std::sin(a), 0});
    m.uvs.insert(m.uvs.end(), {0.5f + 0.45f * std::cos(a), 0.5f + 0.45f * std::sin(a)});
  }
  for (int i = 0; i <= n; ++i) m.indices.push_back(uint32_t(i));  // tip, then the ring
  m.indices.push_back(1u);                                        // closed
  return m;
}

void append_mesh(MeshSpec& a, const MeshSpec& b) {
  const uint32_t base = static_cast<uint32_t>(a.positions.size() / 3);
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  a.uvs.insert(a.uvs.end(), b.uvs.begin(), b.uvs.end());
  for (uint32_t i : b.indices) a.indices.push_back(base + i);
}

MeshSpec unindexed(const MeshSpec& m) {
  MeshSpec out;
  for (uint32_t i : m.indices) {
    out.positions.insert(out.positions.end(), m.positions.begin() + 3 * i, m.positions.begin() + 3 * i + 3);
    if (!m.uvs.empty()) out.uvs.insert(out.uvs.end(), m.uvs.begin() + 2 * i, m.uvs.begin() + 2 * i + 2);
  }
  return out;
}

// ---------------------------------------------------------------- scenes

tinygltf::Model empty_scene() {
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "gltf-warp robustness tests";
  m.meshes.emplace_back();
  tinygltf::Node node;
  node.mesh = 0;
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  return m;
}

namespace {
void append_bytes(void* ctx, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(ctx);
  out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
}

template <typename T>
VertexAttribute int_attr(const std::string& semantic, int components, int ct, bool normalized,
                         const std::vector<T>& v) {
  VertexAttribute a;
  a.semantic = semantic;
  a.component_type = ct;
  a.components = components;
  a.normalized = normalized;
  a.data.resize(v.size() * sizeof(T));
  std::memcpy(a.data.data(), v.data(), a.data.size());
  return a;
}

std::vector<float> normals_of(const MeshSpec& s) {
  std::vector<float> n(s.positions.size(), 0.0f);
  for (size_t v = 0; v < n.size() / 3; ++v) n[3 * v + 2] = 1.0f;
  return n;
}
}  // namespace

namespace {
// A size x size RGB PNG whose texel (x, y) is texel(x, y, rgb), as a new image.
template <typename Texel>
int add_rgb_png(tinygltf::Model& m, int size, Texel&& texel) {
  std::vector<unsigned char> pixels(size_t(size) * size * 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) texel(x, y, &pixels[(size_t(y) * size + x) * 3]);
  tinygltf::Image img;
  stbi_write_png_to_func(append_bytes, &img.image, size, size, 3, pixels.data(), size * 3);
  img.mimeType = "image/png";
  img.as_is = true;
  m.images.push_back(std::move(img));
  return static_cast<int>(m.images.size() - 1);
}
}  // namespace

int add_png_image(tinygltf::Model& m, int size) {
  return add_rgb_png(m, size, [size](int x, int y, unsigned char* p) {
    const bool check = ((x / 4) + (y / 4)) % 2;
    p[0] = static_cast<unsigned char>(check ? 230 : 20 + 200 * x / size);
    p[1] = static_cast<unsigned char>(check ? 40 : 200 * y / size);
    p[2] = static_cast<unsigned char>(90 + (x * y) % 100);
  });
}

int add_flat_png_image(tinygltf::Model& m, int size) {
  return add_rgb_png(m, size, [](int x, int y, unsigned char* p) {
    static constexpr unsigned char kColours[4][3] = {
        {214, 120, 40}, {250, 246, 236}, {40, 30, 28}, {120, 70, 30}};
    const unsigned char* c = kColours[((x + y) / 6) % 4];
    std::copy(c, c + 3, p);
  });
}

int add_gradient_png_image(tinygltf::Model& m, int size) {
  return add_rgb_png(m, size, [size](int x, int y, unsigned char* p) {
    p[0] = static_cast<unsigned char>(255 * x / size);
    p[1] = static_cast<unsigned char>(255 - 255 * y / size);
    p[2] = static_cast<unsigned char>(128 + 100 * std::sin(6.2831853 * (x + y) / size));
  });
}

int add_sampler(tinygltf::Model& m, int wrap_s, int wrap_t) {
  tinygltf::Sampler s;
  s.wrapS = wrap_s;
  s.wrapT = wrap_t;
  m.samplers.push_back(s);
  return static_cast<int>(m.samplers.size() - 1);
}

int add_texture(tinygltf::Model& m, int image, int sampler) {
  tinygltf::Texture t;
  t.source = image;
  t.sampler = sampler;
  m.textures.push_back(t);
  return static_cast<int>(m.textures.size() - 1);
}

int add_material(tinygltf::Model& m, int texture, int tex_coord) {
  tinygltf::Material mat;
  mat.pbrMetallicRoughness.baseColorTexture.index = texture;
  mat.pbrMetallicRoughness.baseColorTexture.texCoord = tex_coord;
  mat.pbrMetallicRoughness.metallicFactor = 0.0;
  m.materials.push_back(mat);
  return static_cast<int>(m.materials.size() - 1);
}

int add_primitive(tinygltf::Model& m, const MeshSpec& spec, int material) {
  tinygltf::Primitive prim;
  VertexAttribute pos = VertexAttribute::from_floats("POSITION", 3, spec.positions);
  prim.attributes["POSITION"] = add_accessor(m, pos, TINYGLTF_TARGET_ARRAY_BUFFER);
  prim.attributes["NORMAL"] = add_accessor(m, VertexAttribute::from_floats("NORMAL", 3, normals_of(spec)),
                                           TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!spec.uvs.empty())
    prim.attributes["TEXCOORD_0"] = add_accessor(m, VertexAttribute::from_floats("TEXCOORD_0", 2, spec.uvs),
                                                 TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!spec.indices.empty()) prim.indices = add_index_accessor(m, spec.indices, spec.positions.size() / 3);
  prim.mode = spec.mode;
  prim.material = material;
  m.meshes[0].primitives.push_back(prim);
  return static_cast<int>(m.meshes[0].primitives.size() - 1);
}

namespace {

// One textured primitive on a fresh scene.
tinygltf::Model single(const MeshSpec& spec, int sampler_s = -1, int sampler_t = -1) {
  tinygltf::Model m = empty_scene();
  const int img = add_png_image(m, 64);
  const int sampler = sampler_s >= 0 ? add_sampler(m, sampler_s, sampler_t) : -1;
  add_primitive(m, spec, add_material(m, add_texture(m, img, sampler)));
  return m;
}

const tinygltf::Primitive& prim_of(const tinygltf::Model& m, size_t mesh, size_t prim) {
  return m.meshes.at(mesh).primitives.at(prim);
}

bool has_ours(const tinygltf::Primitive& p) { return p.extensions.count("GLTFWARP_implicit_texcoords") > 0; }

bool declares(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

}  // namespace

std::vector<VariedModel> varied_models() {
  std::vector<VariedModel> out;
  auto add = [&](std::string name, tinygltf::Model m, bool implicit = true) {
    VariedModel v;
    v.name = std::move(name);
    v.model = std::move(m);
    v.expect_implicit = implicit;
    out.push_back(std::move(v));
    return &out.back();
  };

  // Several primitives per mesh: shared material, another material on the
  // same image, an untextured one, points and lines using the shared
  // material (so it must be cloned for the implicit ones).
  {
    tinygltf::Model m = empty_scene();
    const int img = add_png_image(m, 64);
    const int tex = add_texture(m, img);
    const int mat0 = add_material(m, tex), mat1 = add_material(m, add_texture(m, img));
    add_primitive(m, grid_mesh(6, 5), mat0);
    add_primitive(m, grid_mesh(5, 4, 1.5f, 0), mat0);
    add_primitive(m, grid_mesh(4, 4, 0, 1.5f), mat1);
    MeshSpec plain = grid_mesh(3, 3, 3, 0);
    plain.uvs.clear();
    add_primitive(m, plain, -1);
    MeshSpec points = grid_mesh(3, 3, 0, 3);
    points.indices.clear();
    points.mode = TINYGLTF_MODE_POINTS;
    add_primitive(m, points, mat0);
    MeshSpec lines = grid_mesh(3, 1, 2, 3);
    lines.indices = {0, 1, 1, 2, 2, 3, 4, 5};
    lines.mode = TINYGLTF_MODE_LINE;
    add_primitive(m, lines, mat0);
    auto* v = add("multi-primitive", std::move(m));
    v->check_encoded = [](const tinygltf::Model& e, const std::string& report) {
      ASSERT_EQ(e.meshes.size(), 1u);
      ASSERT_EQ(e.meshes[0].primitives.size(), 6u);
      for (int p : {0, 1, 2}) EXPECT_TRUE(has_ours(prim_of(e, 0, p))) << "primitive " << p << "\n" << report;
      EXPECT_FALSE(has_ours(prim_of(e, 0, 3)));
      EXPECT_EQ(prim_of(e, 0, 4).mode, TINYGLTF_MODE_POINTS);
      EXPECT_EQ(prim_of(e, 0, 5).mode, TINYGLTF_MODE_LINE);
      // Points and lines keep explicit UVs and the unwarped material.
      EXPECT_TRUE(prim_of(e, 0, 4).attributes.count("TEXCOORD_0"));
      EXPECT_NE(prim_of(e, 0, 4).material, prim_of(e, 0, 0).material);
      EXPECT_EQ(prim_of(e, 0, 4).material, prim_of(e, 0, 5).material);
    };
  }
  // KHR_materials_variants mappings with a material index out of range and
  // one that is not a number beside a valid textured variant: the odd ones
  // pass through as written, the valid one is warped with the rest.
  {
    tinygltf::Model m = empty_scene();
    const int img = add_png_image(m, 64);
    const int mat = add_material(m, add_texture(m, img));
    const int variant = add_material(m, add_texture(m, img));
    add_primitive(m, grid_mesh(6, 5), mat);
    tinygltf::Value::Array mappings;
    for (const tinygltf::Value& material :
         {tinygltf::Value(99), tinygltf::Value(std::string("x")), tinygltf::Value(variant)}) {
      tinygltf::Value::Object mapping;
      mapping["material"] = material;
      mapping["variants"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(0)});
      mappings.push_back(tinygltf::Value(mapping));
    }
    tinygltf::Value::Object ext, root, named;
    ext["mappings"] = tinygltf::Value(mappings);
    m.meshes[0].primitives[0].extensions["KHR_materials_variants"] = tinygltf::Value(ext);
    named["name"] = tinygltf::Value(std::string("odd"));
    root["variants"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(named)});
    m.extensions["KHR_materials_variants"] = tinygltf::Value(root);
    m.extensionsUsed.push_back("KHR_materials_variants");
    auto* v = add("odd-material-variants", std::move(m));
    v->check_encoded = [](const tinygltf::Model& e, const std::string& report) {
      const auto& written = prim_of(e, 0, 0).extensions.at("KHR_materials_variants").Get("mappings");
      ASSERT_EQ(written.ArrayLen(), 3u) << report;
      EXPECT_EQ(written.Get(0).Get("material").GetNumberAsInt(), 99);
      EXPECT_TRUE(written.Get(1).Get("material").IsString());
      const int warped = written.Get(2).Get("material").GetNumberAsInt();
      ASSERT_GE(warped, 0);
      ASSERT_LT(size_t(warped), e.materials.size());
      // The variant samples the atlas (the clamp-to-edge texture the warp made).
      const int tex = e.materials[warped].pbrMetallicRoughness.baseColorTexture.index;
      EXPECT_EQ(tex, e.materials[prim_of(e, 0, 0).material].pbrMetallicRoughness.baseColorTexture.index)
          << report;
    };
  }
  // Textures on TEXCOORD_1 are left alone; TEXCOORD_0 is replaced because
  // the base colour uses it.
  {
    tinygltf::Model m = empty_scene();
    const int mat = add_material(m, add_texture(m, add_png_image(m, 64)), 0);
    m.materials[mat].occlusionTexture.index = add_texture(m, add_png_image(m, 32));
    m.materials[mat].occlusionTexture.texCoord = 1;
    add_primitive(m, grid_mesh(6, 6), mat);
    MeshSpec g = grid_mesh(6, 6);
    std::vector<float> uv1(g.uvs.size());
    for (size_t i = 0; i < uv1.size(); ++i) uv1[i] = 0.25f + 0.5f * g.uvs[i];
    m.meshes[0].primitives[0].attributes["TEXCOORD_1"] =
        add_accessor(m, VertexAttribute::from_floats("TEXCOORD_1", 2, uv1), TINYGLTF_TARGET_ARRAY_BUFFER);
    auto* v = add("texcoord1-kept", std::move(m));
    v->check_encoded = [](const tinygltf::Model& e, const std::string&) {
      EXPECT_TRUE(has_ours(prim_of(e, 0, 0)));
      EXPECT_TRUE(prim_of(e, 0, 0).attributes.count("TEXCOORD_1"));
      EXPECT_EQ(e.materials.at(prim_of(e, 0, 0).material).occlusionTexture.texCoord, 1);
    };
  }
  // Only TEXCOORD_1 is sampled: nothing to replace.
  {
    tinygltf::Model m = empty_scene();
    const int mat = add_material(m, add_texture(m, add_png_image(m, 64)), 1);
    MeshSpec g = grid_mesh(5, 5);
    add_primitive(m, g, mat);
    m.meshes[0].primitives[0].attributes["TEXCOORD_1"] =
        add_accessor(m, VertexAttribute::from_floats("TEXCOORD_1", 2, g.uvs), TINYGLTF_TARGET_ARRAY_BUFFER);
    auto* v = add("only-texcoord1", std::move(m), false);
    v->check_encoded = [](const tinygltf::Model& e, const std::string&) {
      EXPECT_FALSE(has_ours(prim_of(e, 0, 0)));
      EXPECT_TRUE(prim_of(e, 0, 0).attributes.count("TEXCOORD_1"));
    };
  }
  // No texture at all.
  {
    tinygltf::Model m = empty_scene();
    tinygltf::Material mat;
    m.materials.push_back(mat);
    add_primitive(m, grid_mesh(4, 4), 0);
    add("untextured", std::move(m), false);
  }
  add("non-indexed", single(unindexed(grid_mesh(5, 4))));
  add("triangle-strip", single(strip_mesh(12)));
  add("triangle-fan", single(fan_mesh(16)));
  // Sparse accessors: POSITION = base data + sparse displacement,
  // TEXCOORD_0 = no bufferView, every value given sparsely.
  {
    tinygltf::Model m = single(grid_mesh(5, 5));
    auto& prim = m.meshes[0].primitives[0];
    const MeshSpec g = grid_mesh(5, 5);
    const uint32_t n = static_cast<uint32_t>(g.positions.size() / 3);
    {
      std::vector<uint16_t> idx = {7, 8, 14};
      std::vector<float> vals;
      for (uint16_t i : idx) vals.insert(vals.end(), {g.positions[3 * i], g.positions[3 * i + 1], 0.4f});
      tinygltf::Accessor& pos = m.accessors[prim.attributes["POSITION"]];
      VertexAttribute ia = int_attr("", 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, false, idx);
      VertexAttribute va = VertexAttribute::from_floats("", 3, vals);
      const int ia_acc = add_accessor(m, ia, 0), va_acc = add_accessor(m, va, 0);
      tinygltf::Accessor& p2 = m.accessors[prim.attributes["POSITION"]];
      (void)pos;
      p2.sparse.isSparse = true;
      p2.sparse.count = 3;
      p2.sparse.indices.bufferView = m.accessors[ia_acc].bufferView;
      p2.sparse.indices.byteOffset = 0;
      p2.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
      p2.sparse.values.bufferView = m.accessors[va_acc].bufferView;
      p2.sparse.values.byteOffset = 0;
      p2.maxValues[2] = 0.4;
      m.accessors.resize(m.accessors.size() - 2);  // the helper accessors; their views stay
    }
    {
      std::vector<uint32_t> idx(n);
      for (uint32_t i = 0; i < n; ++i) idx[i] = i;
      VertexAttribute ia = int_attr("", 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, false, idx);
      VertexAttribute va = VertexAttribute::from_floats("", 2, g.uvs);
      const int ia_acc = add_accessor(m, ia, 0), va_acc = add_accessor(m, va, 0);
      tinygltf::Accessor uv;
      uv.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
      uv.type = TINYGLTF_TYPE_VEC2;
      uv.count = n;
      uv.sparse.isSparse = true;
      uv.sparse.count = static_cast<int>(n);
      uv.sparse.indices.bufferView = m.accessors[ia_acc].bufferView;
      uv.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      uv.sparse.indices.byteOffset = 0;  // tinygltf leaves these uninitialised
      uv.sparse.values.bufferView = m.accessors[va_acc].bufferView;
      uv.sparse.values.byteOffset = 0;
      m.accessors.resize(m.accessors.size() - 2);
      m.accessors.push_back(uv);
      prim.attributes["TEXCOORD_0"] = static_cast<int>(m.accessors.size() - 1);
    }
    add("sparse", std::move(m));
  }
  // Normalized integer UVs (core: unsigned short) and KHR_mesh_quantization
  // ones (signed short): the latter extension must go once TEXCOORD_0 does.
  for (const bool signed_uv : {false, true}) {
    tinygltf::Model m = empty_scene();
    const int mat = add_material(m, add_texture(m, add_png_image(m, 64)));
    MeshSpec g = grid_mesh(6, 5);
    std::vector<float> uvs = g.uvs;
    g.uvs.clear();
    add_primitive(m, g, mat);
    VertexAttribute uv;
    if (signed_uv) {
      std::vector<int16_t> q(uvs.size());
      for (size_t i = 0; i < q.size(); ++i) q[i] = static_cast<int16_t>(std::lround(uvs[i] * 32767.0f));
      uv = int_attr("TEXCOORD_0", 2, TINYGLTF_COMPONENT_TYPE_SHORT, true, q);
      m.extensionsUsed.push_back("KHR_mesh_quantization");
      m.extensionsRequired.push_back("KHR_mesh_quantization");
    } else {
      std::vector<uint16_t> q(uvs.size());
      for (size_t i = 0; i < q.size(); ++i) q[i] = static_cast<uint16_t>(std::lround(uvs[i] * 65535.0f));
      uv = int_attr("TEXCOORD_0", 2, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, true, q);
    }
    m.meshes[0].primitives[0].attributes["TEXCOORD_0"] = add_accessor(m, uv, TINYGLTF_TARGET_ARRAY_BUFFER);
    auto* v = add(signed_uv ? "quantized-uv-short" : "normalized-uv-ushort", std::move(m));
    v->check_encoded = [](const tinygltf::Model& e, const std::string&) {
      EXPECT_TRUE(has_ours(prim_of(e, 0, 0)));
      EXPECT_FALSE(declares(e.extensionsUsed, "KHR_mesh_quantization")) << "no accessor needs it any more";
      EXPECT_FALSE(declares(e.extensionsRequired, "KHR_mesh_quantization"));
    };
  }
  // Quantized positions (KHR_mesh_quantization, node scale): the extension stays.
  {
    tinygltf::Model m = empty_scene();
    const int mat = add_material(m, add_texture(m, add_png_image(m, 64)));
    MeshSpec g = grid_mesh(6, 5);
    std::vector<int16_t> q(g.positions.size());
    for (size_t i = 0; i < q.size(); ++i) q[i] = static_cast<int16_t>(std::lround(g.positions[i] * 1000.0f));
    tinygltf::Primitive prim;
    VertexAttribute pos = int_attr("POSITION", 3, TINYGLTF_COMPONENT_TYPE_SHORT, false, q);
    prim.attributes["POSITION"] = add_accessor(m, pos, TINYGLTF_TARGET_ARRAY_BUFFER);
    prim.attributes["TEXCOORD_0"] =
        add_accessor(m, VertexAttribute::from_floats("TEXCOORD_0", 2, g.uvs), TINYGLTF_TARGET_ARRAY_BUFFER);
    prim.indices = add_index_accessor(m, g.indices, g.positions.size() / 3);
    prim.material = mat;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    m.meshes[0].primitives.push_back(prim);
    m.nodes[0].scale = {0.001, 0.001, 0.001};
    m.extensionsUsed.push_back("KHR_mesh_quantization");
    m.extensionsRequired.push_back("KHR_mesh_quantization");
    auto* v = add("quantized-positions", std::move(m));
    v->check_encoded = [](const tinygltf::Model& e, const std::string&) {
      EXPECT_TRUE(has_ours(prim_of(e, 0, 0)));
      EXPECT_TRUE(declares(e.extensionsUsed, "KHR_mesh_quantization")) << "POSITION still needs it";
      EXPECT_TRUE(declares(e.extensionsRequired, "KHR_mesh_quantization"));
    };
  }
  // UVs outside [0,1] with REPEAT and MIRRORED_REPEAT.
  for (const int wrap : {TINYGLTF_TEXTURE_WRAP_REPEAT, TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT}) {
    MeshSpec g = grid_mesh(6, 6);
    for (float& t : g.uvs) t = 3.0f * t - 1.0f;
    add(wrap == TINYGLTF_TEXTURE_WRAP_REPEAT ? "uv-repeat" : "uv-mirrored-repeat", single(g, wrap, wrap));
  }
  // A mirrored chart (u folded at 0.5) and overlapping charts (four grids on one square).
  {
    MeshSpec g = grid_mesh(8, 4);
    for (size_t i = 0; i < g.uvs.size(); i += 2) g.uvs[i] = std::fabs(2.0f * g.uvs[i] - 1.0f);
    add("mirrored-chart", single(g));
    MeshSpec o = grid_mesh(3, 3);
    append_mesh(o, grid_mesh(3, 3, 1.5f, 0));
    append_mesh(o, grid_mesh(3, 3, 0, 1.5f));
    append_mesh(o, grid_mesh(3, 3, 1.5f, 1.5f));
    add("overlapping-charts", single(o));
  }
  // Non-manifold: a fin of two triangles on an interior edge, and a bowtie vertex.
  {
    MeshSpec g = grid_mesh(4, 4);
    const uint32_t n = static_cast<uint32_t>(g.positions.size() / 3);
    // Interior edge (6, 12) of the 5x5-vertex grid gets two more faces.
    g.positions.insert(g.positions.end(), {0.3f, 0.4f, 0.5f, 0.4f, 0.3f, -0.5f});
    g.uvs.insert(g.uvs.end(), {0.9f, 0.9f, 0.95f, 0.8f});
    g.indices.insert(g.indices.end(), {6, 12, n, 12, 6, n + 1});
    // Bowtie: a triangle touching the grid only at corner vertex 24.
    g.positions.insert(g.positions.end(), {1.3f, 1.1f, 0.0f, 1.1f, 1.3f, 0.0f});
    g.uvs.insert(g.uvs.end(), {0.1f, 0.9f, 0.15f, 0.95f});
    g.indices.insert(g.indices.end(), {24, n + 2, n + 3});
    add("non-manifold", single(g), false);
  }
  // Degenerate faces: repeated index, collinear corners, a duplicated face.
  {
    MeshSpec g = grid_mesh(4, 4);
    g.indices.insert(g.indices.end(), {0, 0, 1, 0, 1, 2, 5, 6, 11, 5, 6, 11});
    add("degenerate", single(g), false);
  }
  // A 32-bit integer attribute past what Draco tabulates (ids from 3e9): the
  // primitive passes through as it came, ids and UVs intact, and the rest of
  // the file is still written (Draco sizes a table by the largest value,
  // 4 bytes a value: 4 GB for values near 2^30 in the fuzzer's input).
  {
    tinygltf::Model m = single(grid_mesh(4, 3));
    VertexAttribute ids;
    ids.semantic = "_ID";
    ids.component_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    ids.components = 1;
    for (uint32_t k = 0; k < 20; ++k) {
      const uint32_t id = 3000000000u + k;
      const auto* b = reinterpret_cast<const uint8_t*>(&id);
      ids.data.insert(ids.data.end(), b, b + 4);
    }
    m.meshes[0].primitives[0].attributes["_ID"] = add_accessor(m, ids, TINYGLTF_TARGET_ARRAY_BUFFER);
    auto* v = add("large-integer-attribute", std::move(m), false);
    v->check_encoded = [](const tinygltf::Model& e, const std::string& report) {
      const tinygltf::Primitive& p = prim_of(e, 0, 0);
      EXPECT_FALSE(has_ours(p)) << report;
      EXPECT_TRUE(p.attributes.count("TEXCOORD_0"));
      EXPECT_NE(report.find("_ID holds integers up to 3000000019"), std::string::npos) << report;
      PrimitiveGeometry g;
      ASSERT_EQ(read_primitive(e, p, g), "");
      const VertexAttribute* got = g.find("_ID");
      ASSERT_NE(got, nullptr);
      ASSERT_EQ(got->count(), 20u);
      for (size_t k = 0; k < 20; ++k) {
        uint32_t id;
        std::memcpy(&id, got->data.data() + 4 * k, 4);
        EXPECT_EQ(id, 3000000000u + k);
      }
    };
  }
  // Many components.
  {
    MeshSpec g = grid_mesh(2, 2);
    for (int k = 1; k < 24; ++k) append_mesh(g, grid_mesh(2, 2, float(k % 6) * 1.3f, float(k / 6) * 1.3f));
    add("many-components", single(g));
  }
  // Huge coordinates (far from the origin, and near float's range).
  for (const float scale : {1e6f, 1e30f}) {
    MeshSpec g = grid_mesh(5, 5);
    for (size_t i = 0; i < g.positions.size(); ++i)
      g.positions[i] = g.positions[i] * scale + (i % 3 == 0 ? 3 * scale : 0);
    add(scale < 1e10f ? "huge-coordinates" : "huge-coordinates-1e30", single(g), false);
  }
  // Closed generated shapes.
  for (const std::string name : {"torus", "sphere"}) {
    tinygltf::Model m;
    if (make_sample_model(name, 400, 64, m).empty()) add("sample-" + name, std::move(m));
  }
  // Data URIs (written as .gltf; the test turns buffers and images into data URIs).
  {
    auto* v = add("data-uris", single(grid_mesh(5, 4)));
    v->container = ".gltf";
  }
  // An image we cannot decode (KTX2), named through KHR_texture_basisu or
  // directly: explicit UVs kept, with the reason in the report.
  for (const bool basisu : {true, false}) {
    tinygltf::Model m = empty_scene();
    tinygltf::Image img;
    const unsigned char ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
    img.image.assign(160, 0);
    std::memcpy(img.image.data(), ktx2, sizeof ktx2);
    img.mimeType = "image/ktx2";
    img.as_is = true;
    m.images.push_back(img);
    tinygltf::Texture t;
    if (basisu) {
      tinygltf::Value::Object ext;
      ext["source"] = tinygltf::Value(0);
      t.extensions["KHR_texture_basisu"] = tinygltf::Value(ext);
      m.extensionsUsed.push_back("KHR_texture_basisu");
      m.extensionsRequired.push_back("KHR_texture_basisu");
    } else {
      t.source = 0;
    }
    m.textures.push_back(t);
    add_primitive(m, grid_mesh(4, 4), add_material(m, 0));
    auto* v = add(basisu ? "ktx2-basisu" : "ktx2-core-source", std::move(m), false);
    v->check_encoded = [](const tinygltf::Model& e, const std::string& report) {
      EXPECT_FALSE(has_ours(prim_of(e, 0, 0)));
      EXPECT_TRUE(prim_of(e, 0, 0).attributes.count("TEXCOORD_0"));
      EXPECT_NE(report.find("explicit UVs kept"), std::string::npos) << "the reason must be reported:\n"
                                                                     << report;
      ASSERT_EQ(e.images.size(), 1u);
      EXPECT_EQ(e.images[0].mimeType, "image/ktx2");
    };
  }
  return out;
}

// ---------------------------------------------------------------- files

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

namespace {
uint32_t u32(const std::string& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}
void put32(std::string& b, uint32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); }
}  // namespace

bool split_glb_file(const std::string& b, Glb& out) {
  if (b.size() < 20 || b.compare(0, 4, "glTF") != 0) return false;
  const uint32_t jlen = u32(b, 12);
  if (20 + size_t{jlen} > b.size()) return false;
  out.json = nlohmann::json::parse(b.substr(20, jlen), nullptr, false);
  if (out.json.is_discarded()) return false;
  out.bin.clear();
  const size_t at = 20 + size_t{jlen};
  if (at + 8 <= b.size()) {
    const uint32_t blen = u32(b, at);
    if (at + 8 + blen <= b.size()) out.bin = b.substr(at + 8, blen);
  }
  return true;
}

std::string join_glb(const Glb& glb) {
  std::string json = glb.json.dump();
  while (json.size() % 4) json.push_back(' ');
  std::string bin = glb.bin;
  while (bin.size() % 4) bin.push_back('\0');
  std::string out = "glTF";
  put32(out, 2);
  put32(out, static_cast<uint32_t>(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
  put32(out, static_cast<uint32_t>(json.size()));
  put32(out, 0x4E4F534Au);
  out += json;
  if (!bin.empty()) {
    put32(out, static_cast<uint32_t>(bin.size()));
    put32(out, 0x004E4942u);
    out += bin;
  }
  return out;
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v =
        uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

std::vector<BadFile> malformed_files(const std::string& dir, const std::string& valid_glb,
                                     const std::string& encoded_glb) {
  std::vector<BadFile> out;
  const std::string valid = read_file(valid_glb), encoded = read_file(encoded_glb);
  Glb base, enc;
  if (!split_glb_file(valid, base) || !split_glb_file(encoded, enc)) return out;
  auto file = [&](const std::string& name, const std::string& bytes, bool must_fail = true) {
    write_file(dir + "/" + name, bytes);
    out.push_back({name, dir + "/" + name, must_fail});
  };
  auto edit = [&](const std::string& name, const Glb& src, const std::function<void(Glb&)>& fn,
                  bool must_fail = true) {
    Glb g = src;
    fn(g);
    file(name, join_glb(g), must_fail);
  };
  auto with_json = [&](const std::string& name, const std::string& json) { file(name, json); };

  // Containers.
  for (const size_t n : {size_t{0}, size_t{3}, size_t{11}, size_t{12}, size_t{19}, size_t{20}, size_t{27},
                         valid.size() / 2, valid.size() - 1})
    file("truncated-" + std::to_string(n) + ".glb", valid.substr(0, n));
  {
    std::string v1 = valid;
    v1[4] = 1;
    file("glb-version-1.glb", v1);
    std::string big = valid;
    const uint32_t len = u32(valid, 8) + 1000;
    std::memcpy(&big[8], &len, 4);
    file("glb-length-too-large.glb", big);
    // A BIN chunk whose payload would end 8 bytes past the file (tinygltf 2.7 accepted it).
    std::string over = valid;
    const size_t at = 20 + u32(valid, 12);
    const uint32_t blen = u32(valid, at) + 8;
    std::memcpy(&over[at], &blen, 4);
    file("glb-bin-overrun.glb", over);
  }
  // JSON.
  with_json("broken.gltf", R"({"asset": {"version": "2.0"}, "meshes": [)");
  with_json("not-object.gltf", "[1, 2, 3]");
  with_json("deep-nesting.gltf", R"({"asset":{"version":"2.0"},"extras":)" + std::string(200000, '[') +
                                     std::string(200000, ']') + "}");
  with_json("huge-number.gltf", R"({"asset":{"version":"2.0"},"accessors":[{"count":1e400}]})");
  edit(
      "broken-json-chunk.glb", base, [](Glb& g) { g.json = nlohmann::json::parse(R"({"asset": 5})"); },
      false);
  // Missing files, forbidden URIs, a FIFO that would block a plain read.
  {
    Glb g = base;
    g.json["buffers"][0]["uri"] = "missing.bin";
    write_file(dir + "/missing-buffer.gltf", g.json.dump());
    out.push_back({"missing-buffer.gltf", dir + "/missing-buffer.gltf", true});
    g.json["buffers"][0]["uri"] = "/etc/hostname";
    write_file(dir + "/absolute-buffer.gltf", g.json.dump());
    out.push_back({"absolute-buffer.gltf", dir + "/absolute-buffer.gltf", true});
    ::mkfifo((dir + "/fifo.bin").c_str(), 0600);
    g.json["buffers"][0]["uri"] = "fifo.bin";
    write_file(dir + "/fifo-buffer.gltf", g.json.dump());
    out.push_back({"fifo-buffer.gltf", dir + "/fifo-buffer.gltf", true});
  }
  // A PNG whose compressed data is damaged: libpng's own messages must not
  // reach stderr beside ours (OpenImageIO's PNG reader let them through).
  edit("png-bad-idat.glb", base, [](Glb& g) {
    const auto& view = g.json["bufferViews"][g.json["images"][0]["bufferView"].get<int>()];
    const size_t at = view.value("byteOffset", size_t{0}) + view["byteLength"].get<size_t>() / 2;
    g.bin[at] = char(g.bin[at] ^ 0x5a);
  });
  edit("missing-image.glb", base, [](Glb& g) {
    g.json["images"][0].erase("bufferView");
    g.json["images"][0]["uri"] = "missing.png";
  });
  // Indices and accessor references.
  const auto& prim0 = base.json["meshes"][0]["primitives"][0];
  const int pos_acc = prim0["attributes"]["POSITION"].get<int>(), idx_acc = prim0["indices"].get<int>();
  const auto view_of = [&](const Glb& g, int acc) {
    return g.json["accessors"][acc]["bufferView"].get<int>();
  };
  const auto view_offset = [&](const Glb& g, int view) {
    return g.json["bufferViews"][view].value("byteOffset", 0) + 0;
  };
  edit("index-out-of-range.glb", base, [&](Glb& g) {
    const size_t at =
        view_offset(g, view_of(g, idx_acc)) + g.json["accessors"][idx_acc].value("byteOffset", 0);
    const uint16_t bad = 60000;
    std::memcpy(&g.bin[at], &bad, 2);
  });
  edit("attribute-accessor-out-of-range.glb", base,
       [](Glb& g) { g.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99; });
  edit("attribute-accessor-negative.glb", base,
       [](Glb& g) { g.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = -7; });
  edit("indices-accessor-out-of-range.glb", base,
       [](Glb& g) { g.json["meshes"][0]["primitives"][0]["indices"] = 99; });
  edit("nan-position.glb", base, [&](Glb& g) {
    const size_t at =
        view_offset(g, view_of(g, pos_acc)) + g.json["accessors"][pos_acc].value("byteOffset", 0) + 4;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(&g.bin[at], &nan, 4);
  });
  edit("inf-position.glb", base, [&](Glb& g) {
    const size_t at =
        view_offset(g, view_of(g, pos_acc)) + g.json["accessors"][pos_acc].value("byteOffset", 0);
    const float inf = std::numeric_limits<float>::infinity();
    std::memcpy(&g.bin[at], &inf, 4);
  });
  // Sizes.
  edit("bufferview-past-end.glb", base, [&](Glb& g) { g.json["bufferViews"][0]["byteLength"] = 1u << 30; });
  edit("bufferview-offset-past-end.glb", base,
       [&](Glb& g) { g.json["bufferViews"][0]["byteOffset"] = 4000000000ull; });
  edit("buffer-larger-than-bin.glb", base, [&](Glb& g) { g.json["buffers"][0]["byteLength"] = 1u << 31; });
  edit("absurd-count.glb", base, [&](Glb& g) { g.json["accessors"][pos_acc]["count"] = 200000000; });
  edit("absurd-count-2.glb", base, [&](Glb& g) { g.json["accessors"][pos_acc]["count"] = 4000000000ull; });
  edit("huge-zero-accessor.glb", base, [&](Glb& g) {
    g.json["accessors"].push_back({{"componentType", 5126}, {"type", "MAT4"}, {"count", 200000000}});
    g.json["meshes"][0]["primitives"][0]["attributes"]["_HUGE"] = g.json["accessors"].size() - 1;
  });
  edit("accessor-offset-past-view.glb", base,
       [&](Glb& g) { g.json["accessors"][pos_acc]["byteOffset"] = 1u << 30; });
  edit("stride-below-element.glb", base,
       [&](Glb& g) { g.json["bufferViews"][view_of(g, pos_acc)]["byteStride"] = 4; });
  edit("image-view-past-end.glb", base, [&](Glb& g) {
    const int v = g.json["images"][0]["bufferView"].get<int>();
    g.json["bufferViews"][v]["byteLength"] = g.json["buffers"][0]["byteLength"].get<size_t>() + 64;
  });
  edit("sparse-index-out-of-range.glb", base, [&](Glb& g) {
    g.json["accessors"][pos_acc]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", view_of(g, idx_acc)}, {"componentType", 5123}, {"byteOffset", 0}}},
        {"values", {{"bufferView", view_of(g, pos_acc)}}}};
    const size_t at = view_offset(g, view_of(g, idx_acc));
    const uint16_t bad = 65000;
    std::memcpy(&g.bin[at], &bad, 2);
  });
  edit("sparse-count-absurd.glb", base, [&](Glb& g) {
    g.json["accessors"][pos_acc]["sparse"] = {
        {"count", 100000000},
        {"indices", {{"bufferView", view_of(g, idx_acc)}, {"componentType", 5125}}},
        {"values", {{"bufferView", view_of(g, pos_acc)}}}};
  });
  // Wrong JSON types.
  edit(
      "meshes-not-array.glb", base,
      [](Glb& g) {
        g.json["meshes"] = {{"a", 1}};
      },
      false);
  edit("attributes-array.glb", base, [](Glb& g) {
    g.json["meshes"][0]["primitives"][0]["attributes"] = {1, 2};
  });
  edit(
      "primitive-extensions-number.glb", base,
      [](Glb& g) { g.json["meshes"][0]["primitives"][0]["extensions"] = 3; }, false);
  edit("draco-ext-number.glb", base, [](Glb& g) {
    g.json["meshes"][0]["primitives"][0]["extensions"] = {{"KHR_draco_mesh_compression", 5}};
  });
  edit("draco-ext-array.glb", base, [](Glb& g) {
    g.json["meshes"][0]["primitives"][0]["extensions"] = {{"KHR_draco_mesh_compression", {1, 2}}};
  });
  edit("ours-ext-string.glb", base, [](Glb& g) {
    g.json["meshes"][0]["primitives"][0]["extensions"] = {{"GLTFWARP_implicit_texcoords", "x"}};
  });
  edit(
      "texture-transform-wrong-type.glb", base,
      [](Glb& g) {
        g.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
            {"KHR_texture_transform",
             {{"offset", "a"}, {"scale", 5}, {"rotation", {1}}, {"texCoord", 1e30}}}};
      },
      false);
  edit(
      "texcoord-huge.glb", base,
      [](Glb& g) { g.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1e30; },
      false);
  edit(
      "texture-source-huge.glb", base, [](Glb& g) { g.json["textures"][0]["source"] = 1e30; }, false);
  edit(
      "material-out-of-range.glb", base,
      [](Glb& g) { g.json["meshes"][0]["primitives"][0]["material"] = 77; }, false);
  edit(
      "texture-out-of-range.glb", base,
      [](Glb& g) { g.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 55; },
      false);
  edit(
      "mode-unknown.glb", base, [](Glb& g) { g.json["meshes"][0]["primitives"][0]["mode"] = 9; }, false);

  // The encoded file: Draco data, our bitstream, their extension objects.
  const auto& eprim = enc.json["meshes"][0]["primitives"][0];
  if (eprim.contains("extensions") && eprim["extensions"].contains("KHR_draco_mesh_compression") &&
      eprim["extensions"].contains("GLTFWARP_implicit_texcoords")) {
    const int draco_view = eprim["extensions"]["KHR_draco_mesh_compression"]["bufferView"].get<int>();
    const int our_view = eprim["extensions"]["GLTFWARP_implicit_texcoords"]["bufferView"].get<int>();
    auto flip_view = [&](const std::string& name, int view, double where, uint8_t mask) {
      edit(
          name, enc,
          [&](Glb& g) {
            const size_t off = g.json["bufferViews"][view].value("byteOffset", 0);
            const size_t len = g.json["bufferViews"][view]["byteLength"].get<size_t>();
            const size_t at = off + std::min(len - 1, static_cast<size_t>(where * double(len)));
            g.bin[at] = static_cast<char>(g.bin[at] ^ mask);
          },
          false);
    };
    for (const double w : {0.0, 0.01, 0.05, 0.2, 0.5, 0.9, 0.999}) {
      flip_view("corrupt-draco-" + std::to_string(int(w * 1000)) + ".glb", draco_view, w, 0x5A);
      flip_view("corrupt-bitstream-" + std::to_string(int(w * 1000)) + ".glb", our_view, w, 0xA5);
    }
    auto ext_edit = [&](const std::string& name, const std::function<void(nlohmann::json&)>& fn,
                        bool must_fail = true) {
      edit(
          name, enc, [&](Glb& g) { fn(g.json["meshes"][0]["primitives"][0]["extensions"]); }, must_fail);
    };
    ext_edit("enc-ours-number.glb", [](nlohmann::json& e) { e["GLTFWARP_implicit_texcoords"] = 5; });
    ext_edit("enc-ours-view-string.glb",
             [](nlohmann::json& e) { e["GLTFWARP_implicit_texcoords"]["bufferView"] = "x"; });
    ext_edit("enc-ours-view-huge.glb",
             [](nlohmann::json& e) { e["GLTFWARP_implicit_texcoords"]["bufferView"] = 1e30; });
    ext_edit("enc-ours-view-negative.glb",
             [](nlohmann::json& e) { e["GLTFWARP_implicit_texcoords"]["bufferView"] = -1; });
    ext_edit("enc-ours-view-is-draco.glb",
             [&](nlohmann::json& e) { e["GLTFWARP_implicit_texcoords"]["bufferView"] = draco_view; });
    ext_edit("enc-draco-array.glb",
             [](nlohmann::json& e) { e["KHR_draco_mesh_compression"] = nlohmann::json::array(); });
    ext_edit("enc-draco-view-huge.glb",
             [](nlohmann::json& e) { e["KHR_draco_mesh_compression"]["bufferView"] = 1e30; });
    ext_edit("enc-draco-attr-string.glb",
             [](nlohmann::json& e) { e["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = "a"; });
    ext_edit("enc-draco-attr-wrong-id.glb",
             [](nlohmann::json& e) { e["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 42; });
    ext_edit("enc-draco-view-is-ours.glb",
             [&](nlohmann::json& e) { e["KHR_draco_mesh_compression"]["bufferView"] = our_view; });
    edit(
        "enc-draco-view-truncated.glb", enc,
        [&](Glb& g) {
          auto& v = g.json["bufferViews"][draco_view];
          v["byteLength"] = v["byteLength"].get<size_t>() / 2;
        },
        false);
    edit("enc-bitstream-view-truncated.glb", enc, [&](Glb& g) {
      auto& v = g.json["bufferViews"][our_view];
      v["byteLength"] = v["byteLength"].get<size_t>() / 2;
    });
    // Found by fuzz_gltf_decode: a Draco POSITION declared VEC2 (min/max were
    // written for three components).
    edit(
        "enc-position-vec2.glb", enc,
        [](Glb& g) {
          g.json["accessors"][g.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()]
                ["type"] = "VEC2";
        },
        false);
    edit(
        "enc-no-position.glb", enc,
        [](Glb& g) { g.json["meshes"][0]["primitives"][0]["attributes"].erase("POSITION"); }, false);
    edit(
        "enc-mode-lines.glb", enc, [](Glb& g) { g.json["meshes"][0]["primitives"][0]["mode"] = 1; }, false);
  }
  return out;
}

}  // namespace gltfwarp::test
