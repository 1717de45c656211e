#include "codec/encode/primitive_partition.h"

#include <algorithm>
#include <cmath>

#include "codec/decode/embedding_mesh.h"
#include "codec/encode/atlas/pages.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/partition/source_charts.h"
#include "codec/encode/texture/seam_continuity.h"

namespace gltfwarp {
namespace {

// Largest distance between a source position and its Draco-decoded copy.
double quantization_tolerance(const VertexAttribute& pos, int bits) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t e = 0; e < pos.count(); ++e)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min<double>(lo[i], pos.get(e, i));
      hi[i] = std::max<double>(hi[i], pos.get(e, i));
    }
  double range = 0;
  for (int i = 0; i < 3; ++i) range = std::max(range, hi[i] - lo[i]);
  const double step = range / double((1u << std::clamp(bits, 1, 30)) - 1);
  return step * 1.01 + 1e-7 * std::max(1.0, range);
}

std::vector<double> face_texels(std::span<const double> corner_xy, std::span<const float> source_uv,
                                uint32_t image_w, uint32_t image_h, const EncodeOptions& options) {
  std::vector<double> face_density;
  const double factor = atlas_density(corner_xy, source_uv, image_w, image_h, options, face_density);
  return estimated_face_texels(corner_xy, face_density, factor);
}

}  // namespace

double atlas_density(std::span<const double> corner_xy, std::span<const float> source_uv, uint32_t image_w,
                     uint32_t image_h, const EncodeOptions& options, std::vector<double>& face_density) {
  if (options.texel_density > 0) return options.texel_density;
  face_density = layout_texel_density(corner_xy, source_uv, image_w, image_h);
  return options.texel_density_factor;
}

EmbedOptions partition_options(const EncodeOptions& options, std::span<const double> face_density,
                               std::span<const uint32_t> face_chart) {
  EmbedOptions eo;
  eo.tau = options.tau;
  eo.mode = options.greedy_partition ? PartitionMode::greedy : PartitionMode::compact;
  eo.solve_merge = options.mixed_layout;
  // Density-aware partition: faces of very different source texel density
  // land in different patches, so the per-patch scale can keep each one's detail.
  eo.face_density = face_density;
  eo.face_chart = face_chart;
  // Inside one source chart densities rarely jump (artists give detail its
  // own chart), so the density rule only guards the extreme cases there.
  // Measured with charts: ratio 8 costs Duck 658 seams against 557 at 32 and
  // 532 off, at the same 42.6 dB and bytes; CesiumMilkTruck is 284 KB at 8
  // and 32 and 297 KB with the rule off.
  if (!face_chart.empty()) eo.max_density_ratio = 32.0;
  return eo;
}

PreparedPartition prepare_partition(const PrimitiveGeometry& geom, std::span<const float> source_corner_uv,
                                    const PartitionContext& context, const EncodeOptions& options) {
  PreparedPartition out;
  const VertexAttribute& src_pos = *geom.find("POSITION");
  double tolerance = 1e-9;
  if (options.raw_geometry) {
    out.decoded = geom;
    out.geometry_bytes = plain_geometry_bytes(geom);
  } else {
    out.error = draco_round_trip(geom, options.draco, out.encoded, out.decoded);
    if (!out.error.empty()) return out;
    out.geometry_bytes = out.encoded.bytes.size();
    tolerance = quantization_tolerance(src_pos, options.draco.position_bits) * std::sqrt(3.0);
  }
  if (out.decoded.triangles.empty()) return out;

  std::vector<uint32_t> point_to_vertex;
  const VertexAttribute& decoded_pos = *out.decoded.find("POSITION");
  out.tri = embedding_mesh(decoded_pos, out.decoded.triangles, point_to_vertex);
  out.match = match_corners(src_pos.to_floats(), geom.triangles, decoded_pos.to_floats(),
                            out.decoded.triangles, tolerance);
  out.source_uv.resize(out.decoded.triangles.size() * 2);
  for (size_t c = 0; c < out.decoded.triangles.size(); ++c)
    for (int i = 0; i < 2; ++i)
      out.source_uv[2 * c + i] = source_corner_uv[2 * out.match.source_corner[c] + i];

  const uint32_t image_w = context.image_w, image_h = context.image_h;
  if (image_w > 0) out.face_density = triangle_texel_density(out.tri, out.source_uv, image_w, image_h);
  if (options.keep_source_charts && image_w > 0) {
    // Seams the source's own textures hide do not bound charts. Measured
    // (seams, images, dB): Duck 557 -> 516, 6.8 -> 6.5 KB, 41.7 -> 41.1;
    // Fox 176 -> 143, 20.8 -> 23.4 KB, 39.6 -> 40.0; CesiumMilkTruck
    // 711 -> 640, 278 -> 289 KB at 38.5. The same at tolerances from 1/4
    // to 8/32: the seams crossed are ones where both sides show one colour.
    const bool textures = !context.seam_textures.empty();
    out.face_chart = source_charts(
        out.tri, out.source_uv, textures ? texture_seam_test(context.seam_textures) : SeamTest(),
        textures ? texture_seam_test(context.seam_textures, kSlitCrossable) : SeamTest());
  }
  // With texel reuse, faces that repeat source texels get copy patches the
  // packer can land on their originals (twin_partition.h).
  auto run_embed = [&] {
    const EmbedOptions eo = partition_options(options, out.face_density, out.face_chart);
    if (options.texel_reuse) {
      out.twins = embed_with_twins(out.tri, out.source_uv, eo);
    } else {
      out.twins = TwinEmbedding{};
      out.twins.embedding = embed(out.tri, eo);
    }
  };
  run_embed();
  const Embedding& er = out.twins.embedding;
  // A patch larger than a page could not go to pages (a flat ground plane
  // under a big texture is one patch): its faces are split into regions of
  // about half a page that no patch may cross, and the mesh is embedded
  // again, a few times at most.
  for (int round = 0; round < 3 && er.status == LayoutStatus::ok && options.max_pages > 1 && image_w > 0;
       ++round) {
    std::vector<uint32_t> regions =
        split_large_patches(out.tri, er.patch_of_face, er.patch_count,
                            face_texels(er.corner_xy, out.source_uv, image_w, image_h, options),
                            page_capacity(options.max_atlas_size), out.face_chart);
    if (regions.empty()) break;
    out.face_chart = std::move(regions);
    run_embed();
  }
  return out;
}

}  // namespace gltfwarp
