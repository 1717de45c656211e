// Generators of varied and of malformed glTF files for the robustness tests
// (issue 7). Everything is built in the test, small and programmatic: valid
// scenes as tinygltf::Model objects (grids, strips, fans, non-manifold and
// degenerate meshes, sparse and quantized accessors, several primitives and
// materials...), bad files as JSON or GLB bytes edited by hand.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

namespace gltfwarp::test {

// Geometry of one primitive before it becomes accessors.
struct MeshSpec {
  std::vector<float> positions;   // xyz per vertex
  std::vector<float> uvs;         // uv per vertex (empty: no TEXCOORD_0)
  std::vector<uint32_t> indices;  // empty: non-indexed
  int mode = TINYGLTF_MODE_TRIANGLES;
};

// A gently curved (nx x ny)-quad grid at `origin`, UVs spanning [0,1]^2.
MeshSpec grid_mesh(int nx, int ny, float origin_x = 0, float origin_y = 0);
// The same grid as one triangle strip (ny = 1 row) or a fan around a cone tip.
MeshSpec strip_mesh(int nx);
MeshSpec fan_mesh(int n);
// Appends `b` to `a` (indices offset); both must be indexed triangle lists.
void append_mesh(MeshSpec& a, const MeshSpec& b);
// Expands indices into a non-indexed triangle list.
MeshSpec unindexed(const MeshSpec& m);

// A scene with one node and one (empty) mesh, no buffers yet.
tinygltf::Model empty_scene();
// A PNG image (a procedural checker, size x size), a texture on it and a
// base-colour material using texCoord `tex_coord`. Returns the material.
int add_png_image(tinygltf::Model& m, int size);
// A size x size PNG of smooth colour ramps (no detail finer than the image),
// unlike add_png_image's 4-texel checker: it survives a warp at 38 dB.
int add_gradient_png_image(tinygltf::Model& m, int size);
// A size x size PNG of four flat colours in diagonal bands 6 texels wide, as
// low-poly models paint (the Fox): small as PNG, more as JPEG at q85, whose
// blocks pay for every edge (even with optimised Huffman tables; flat
// quadrants no longer do).
int add_flat_png_image(tinygltf::Model& m, int size);
int add_texture(tinygltf::Model& m, int image, int sampler = -1);
int add_material(tinygltf::Model& m, int texture, int tex_coord = 0);
int add_sampler(tinygltf::Model& m, int wrap_s, int wrap_t);
// Appends a primitive made of `spec` to mesh 0 with float accessors.
// Returns the primitive index.
int add_primitive(tinygltf::Model& m, const MeshSpec& spec, int material);

// One valid-but-varied scene, with what the encoder must do with it.
struct VariedModel {
  std::string name;
  tinygltf::Model model;
  std::string container = ".glb";  // .glb or .gltf
  bool expect_implicit = true;     // at least one primitive loses TEXCOORD_0
  // Extra checks on the encoded model (empty: none).
  std::function<void(const tinygltf::Model& encoded, const std::string& report)> check_encoded;
};
std::vector<VariedModel> varied_models();

// A file on disk that must be refused (must_fail) or may pass.
struct BadFile {
  std::string name;
  std::string path;
  bool must_fail = true;
};

// GLB container helpers for hand-editing (no validation beyond the header).
struct Glb {
  nlohmann::json json;
  std::string bin;
};
bool split_glb_file(const std::string& bytes, Glb& out);
std::string join_glb(const Glb& glb);
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& bytes);
std::string base64(const std::string& bytes);

// Writes malformed variants of `valid_glb` (a small plain textured scene)
// and of `encoded_glb` (its encoded form) into `dir`.
std::vector<BadFile> malformed_files(const std::string& dir, const std::string& valid_glb,
                                     const std::string& encoded_glb);

}  // namespace gltfwarp::test
