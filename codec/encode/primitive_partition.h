// The costly, pure half of preparing a primitive for implicit UVs
// (prepare_implicit_primitive): its Draco round trip, the embedding mesh,
// the source UV of each decoded corner, and the partition with its page
// regions. Nothing here reads or writes the model, so the parts of a cut
// primitive can be prepared side by side while the encoder's loop, which
// commits them one by one, waits (prefetch in implicit_uv_encoder.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "codec/core/corner_match.h"
#include "codec/core/mesh.h"
#include "codec/encode/encoder.h"
#include "codec/encode/partition/twin_partition.h"
#include "codec/encode/texture/texture_sampler.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {

// What the model says about the primitive's textures.
struct PartitionContext {
  uint32_t image_w = 0, image_h = 0;  // largest_uv0_image; 0: no readable image
  // The seam test's textures (seam_continuity.h); empty: every source seam bounds a chart.
  std::span<const TextureSampler> seam_textures;
};

struct PreparedPartition {
  std::string error;                 // Draco refused the geometry or failed
  DracoEncoded encoded;              // empty with raw geometry
  PrimitiveGeometry decoded;         // what every decoder sees
  size_t geometry_bytes = 0;         // Draco's bytes, or the plain arrays'
  TriMesh tri;                       // embedding mesh (decoded positions welded exactly)
  CornerMatch match;                 // decoded corner -> source corner
  std::vector<float> source_uv;      // TEXCOORD_0 of the source, 2 per corner of `tri`
  std::vector<double> face_density;  // source texels per unit, per face (empty: no image)
  std::vector<uint32_t> face_chart;  // the charts the last embedding ran with (empty: none)
  TwinEmbedding twins;               // the partition; not run when `decoded` has no triangle
};

// `geom`: the primitive welded, without TEXCOORD_0 and TANGENT, every
// POSITION finite; `source_corner_uv`: its TEXCOORD_0 per corner, as read
// before the weld.
PreparedPartition prepare_partition(const PrimitiveGeometry& geom, std::span<const float> source_corner_uv,
                                    const PartitionContext& context, const EncodeOptions& options);

// The partition's options for these densities and charts.
EmbedOptions partition_options(const EncodeOptions& options, std::span<const double> face_density,
                               std::span<const uint32_t> face_chart);

// The density the atlas will give the faces: per face (face_density, from
// the layout and the source UVs) times the returned factor, or the fixed
// --texel-density (face_density left empty).
double atlas_density(std::span<const double> corner_xy, std::span<const float> source_uv, uint32_t image_w,
                     uint32_t image_h, const EncodeOptions& options, std::vector<double>& face_density);

}  // namespace gltfwarp
