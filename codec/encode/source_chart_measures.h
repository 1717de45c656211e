// The source's own UV charts measured beside our patches (issue 19): the
// yardstick of the partition's seams. An author's layout with fewer seams
// than ours may stretch faces past tau, or hold charts that are no disc (a
// tube's slit), which no patch can be; the edges between the charts the
// partition keeps to are seams of ours whatever it does. Report only: the
// encoded file does not depend on any of it.
#pragma once

#include <cstdint>
#include <span>

#include "codec/core/mesh.h"
#include "codec/encode/encode_report.h"

namespace gltfwarp {

// mesh: the embedding mesh; source_uv: TEXCOORD_0, 2 floats per corner;
// partition_charts: the charts the partition ran with, one per face (empty:
// none); image_w x image_h: the texels the UVs address (0: unknown, no
// stretch measured); tau: the encoder's distortion bound.
SourceChartMeasures measure_source_charts(const TriMesh& mesh, std::span<const float> source_uv,
                                          std::span<const uint32_t> partition_charts, uint32_t image_w,
                                          uint32_t image_h, double tau);

}  // namespace gltfwarp
