// The texture slots of glTF materials: which textures a material samples,
// through which texcoord set, in which colour space, with which
// KHR_texture_transform. Covers the core slots and every "*Texture" slot of
// material extensions (KHR_materials_*), so a warp reaches all of them.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace gltfwarp {

enum class ColorSpace { srgb, linear };

struct TextureSlot {
  int material = -1;
  std::string extension;  // empty for core slots, else e.g. "KHR_materials_clearcoat"
  std::string key;        // "baseColorTexture", "normalTexture", "clearcoatNormalTexture", ...
  int texture = -1;
  int tex_coord = 0;  // effective set (KHR_texture_transform's texCoord wins)
  ColorSpace color_space = ColorSpace::linear;
  bool normal_map = false;
  bool has_transform = false;
  // uv' = [m0 m1 m2; m3 m4 m5] * (u, v, 1): KHR_texture_transform as a matrix.
  std::array<double, 6> transform{1, 0, 0, 0, 1, 0};

  std::string name() const { return extension.empty() ? key : extension + "." + key; }
};

// All texture slots of material `m` (an empty list for an invalid index).
std::vector<TextureSlot> texture_slots(const tinygltf::Model& model, int material);

// Points `slot` at `texture`, with texCoord 0 and without KHR_texture_transform
// (the transform is baked into the warped image).
void retarget_slot(tinygltf::Model& model, const TextureSlot& slot, int texture);

// Every material a primitive can show: its own (if any), then those its
// KHR_materials_variants mappings name, each once, in order of appearance.
// Indices are as written (the caller checks them against the model).
std::vector<int> primitive_materials(const tinygltf::Primitive& prim);

// Makes the primitive show material `to` wherever it showed `from`: its own
// material and every KHR_materials_variants mapping that names `from`.
void replace_primitive_material(tinygltf::Primitive& prim, int from, int to);

// Image index a texture samples, or -1: its `source`, else the image its
// EXT_texture_webp names (a WebP image has no core `source`).
int texture_image(const tinygltf::Model& model, int texture);

// Makes `texture` sample `image`: through `source` for PNG and JPEG, through
// EXT_texture_webp (declared used and required: there is no fallback image)
// for a WebP image.
void set_texture_image(tinygltf::Model& model, int texture, int image);

// set_texture_image on every texture that samples `image` (after its bytes
// changed coder).
void point_textures_at_image(tinygltf::Model& model, int image);

// Gives `image` new encoded bytes of type `mime`, then points its textures
// at it. The image leaves its bufferView or URI: an image read from a .glb
// keeps its view, which the writer copies as it is (compact_buffers), so
// bytes set beside it would be lost and the file would name PNG bytes
// image/jpeg. The old view goes when nothing else uses it.
void replace_image_bytes(tinygltf::Model& model, int image, std::vector<unsigned char> bytes,
                         const std::string& mime);

// The wrapS and wrapT of a texture's sampler (glTF enums); REPEAT, glTF's
// default, when the texture has no valid sampler.
void texture_wraps(const tinygltf::Model& model, int texture, int& wrap_s, int& wrap_t);

}  // namespace gltfwarp

namespace gltfwarp {

// Drops the textures in `candidates` that no material references any more,
// then the images no texture references any more (only images that a dropped
// texture used), renumbering every reference the core and the known
// extensions make. Textures and images outside the candidates stay: an
// extension we do not know might name them.
void drop_unused_textures(tinygltf::Model& model, const std::vector<int>& candidates);

}  // namespace gltfwarp
