// Texel density of a source texture map: how many texels per model unit the
// original UVs give each triangle, and the global texel scale ("--texel-density
// auto") that keeps the original's detail in the rebuilt atlas.
//
// Source: the density measure is the square root of the ratio of a triangle's
// texel-space area to its 3D area (the isotropic scale of the affine map
// 3D -> texels, as in the "texel density" of Sander et al., "Texture Mapping
// Progressive Meshes", SIGGRAPH 2001, and xatlas' texelsPerUnit).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"

namespace gltfwarp {

// One primitive as it samples one source image through TEXCOORD_0.
struct DensityPrimitive {
  const TriMesh* mesh = nullptr;
  std::span<const float> source_uv;  // 2 per corner (3 per face), transform already baked in
  uint32_t image_width = 0;          // largest image the primitive samples through TEXCOORD_0
  uint32_t image_height = 0;
};

enum class DensityMode : uint8_t {
  preserve_used_texels,  // scale whose atlas holds as many texels as the distinct source
                         // texels the UV map touches (overlapping/mirrored charts count once)
  preserve_texel_count,  // scale whose atlas holds as many texels as the source triangles
                         // cover (overlapping charts count once per use: more detail, more bytes)
  percentile,            // area-weighted percentile of per-triangle density (keeps the detail
                         // where the artist put it, costs texels elsewhere)
};

struct TexelDensityOptions {
  DensityMode mode = DensityMode::preserve_used_texels;  // default: same texel budget as source
  double percentile = 0.9;                               // for DensityMode::percentile, in (0, 1]
  double min_scale = 1e-9;  // the result where no face has both a 3D and a texel area (texels per unit);
                            // otherwise the floor is one texel over the whole surface
};

struct TexelDensityReport {
  double texel_scale = 0;   // chosen texels per model unit
  double mean_density = 0;  // area-weighted mean of per-triangle density
  double p50_density = 0;   // area-weighted median
  double p90_density = 0;   // area-weighted 90th percentile
  double max_density = 0;
  double source_texels = 0;    // sum of triangles' texel-space areas (overlaps count twice)
  double used_texels = 0;      // distinct source texels whose centre a UV triangle covers
                               // (wrapped into the image, per image size; summed over primitives
                               // that sample different image sizes)
  double surface_area = 0;     // sum of triangles' 3D areas
  uint32_t triangles = 0;      // triangles with non-zero 3D area
  uint32_t degenerate_uv = 0;  // triangles with zero texel-space area
};

// Area of face f in 3D (model units squared).
double face_area3d(const TriMesh& mesh, uint32_t f);
// Area of face f in the texels of a w x h image, from per-corner UVs (6 per face).
double face_area_texels(std::span<const float> uv, uint32_t f, double w, double h);
// Area of face f of a layout (corner_xy: 6 per face, layout units squared).
inline double layout_face_area(std::span<const double> corner_xy, size_t f) {
  const double* c = &corner_xy[6 * f];
  return 0.5 * std::abs((c[2] - c[0]) * (c[5] - c[1]) - (c[3] - c[1]) * (c[4] - c[0]));
}

// Texels per model unit of each face (0 for faces without 3D area).
std::vector<double> triangle_texel_density(const TriMesh& mesh, std::span<const float> source_uv,
                                           uint32_t image_width, uint32_t image_height);

// The affine map of face f from its layout (corner_xy, 6 per face) to its
// source texels (source_uv, 6 per face, times width and height):
// j = {dtx/dx, dtx/dy, dty/dx, dty/dy}. False where the layout face has no
// area or is not finite.
bool layout_to_source_jacobian(std::span<const double> corner_xy, std::span<const float> source_uv, size_t f,
                               double width, double height, double j[4]);

// Texels per layout unit that each face needs to keep its source detail:
// the geometric mean of the largest singular value of the affine map from
// the face's layout (corner_xy, 2 per corner) to its source texels
// (source_uv times the image size) and of its area scale sqrt|det|. The
// layout stretches 3D lengths by up to tau, so this, not the 3D density, is
// what the atlas must match. The largest singular value alone never minifies
// but pays full density along a source's coarse direction; the area scale
// alone keeps the texel count but blurs the fine direction of anisotropic
// maps (on the Duck, the mean keeps the quality of the largest value at
// fewer bytes, and the area scale alone loses it; figures: scripts/bench,
// benchmarks/results/). 0 for faces degenerate in either space.
std::vector<double> layout_texel_density(std::span<const double> corner_xy, std::span<const float> source_uv,
                                         uint32_t image_width, uint32_t image_height);

// One patch's density as the packer scales it (PackOptions::density_quantile).
struct PatchDensity {
  double area = 0;     // layout area of its faces with a density
  double density = 0;  // the area-weighted quantile of their densities (RMS with quantile <= 0); 0: none
  double squared = 0;  // sum over those faces of area * density^2
};

// Per patch, from each face's layout (corner_xy, 6 per face) and density
// (layout_texel_density); faces without area or density are skipped.
// Requires patch_of_face[f] < patch_count.
std::vector<PatchDensity> patch_densities(std::span<const double> corner_xy,
                                          std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                                          std::span<const double> face_density, double quantile);

// Global texel scale for a set of primitives that share an atlas.
TexelDensityReport auto_texel_scale(std::span<const DensityPrimitive> prims,
                                    const TexelDensityOptions& options = {});

}  // namespace gltfwarp
