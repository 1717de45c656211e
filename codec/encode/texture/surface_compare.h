// Quality of a round trip measured on the surface: the colour a viewer would
// fetch at points of every triangle, from the source texture at the source
// UVs against the decoded texture at the decoded UVs. Texture-space, bilinear,
// no lighting: a stand-in for an unlit render that needs no browser.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace gltfwarp {

struct SurfaceComparison {
  double psnr = 0;     // dB over all samples, 8-bit scale (inf when identical)
  double rmse = 0;     // in 0..255 units
  double max_abs = 0;  // largest channel difference seen
  size_t samples = 0;
  size_t primitives = 0;  // textured primitives compared
  size_t unmatched_faces = 0;
  std::string error;  // empty when the comparison ran
};

// What each surface point weighs in the mean.
enum class SampleWeight : uint8_t {
  // Every point alike, about one per source texel: the mean over the
  // source's texels, so a face weighs its UV area. Detail an artist gave
  // many texels (eyes, labels) counts as much as it holds.
  source_texel,
  // Each point its face's 3D area over the face's point count: the mean over
  // the surface itself, as a view that sees all of it evenly shows it. A face
  // whose UVs cover many texels on little surface (a cone's apex under a
  // polar map) weighs its area, not its texels.
  surface_area,
};

struct SurfaceCompareOptions {
  std::string slot = "baseColorTexture";  // which material slot to compare
  // Interior points per triangle; 0: about one per source texel the face
  // covers (an n x n subdivision, 2 <= n <= 64), as benchmarks/compare does.
  int samples_per_face = 0;
  // Compare lighting instead of colour: the slot (a normal map) lights each
  // point through the file's own NORMAL and TANGENT under three fixed lights
  // (Lambert, 0..255 per light). Primitives without both are skipped.
  bool lit = false;
  SampleWeight weight = SampleWeight::source_texel;
};

// `source` and `decoded` are the same scene before encoding and after
// decoding (meshes and primitives in the same order). Primitives whose
// material has no texture in the slot are skipped.
SurfaceComparison compare_surface(const tinygltf::Model& source, const tinygltf::Model& decoded,
                                  const SurfaceCompareOptions& options = {});

}  // namespace gltfwarp
