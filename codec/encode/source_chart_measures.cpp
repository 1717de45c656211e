// The source's own UV charts beside our patches (source_chart_measures.h).
#include "codec/encode/source_chart_measures.h"

#include <algorithm>
#include <vector>

#include "codec/core/layout_report.h"
#include "codec/core/layout_solve.h"
#include "codec/core/topology.h"
#include "codec/encode/partition/source_charts.h"

namespace gltfwarp {

SourceChartMeasures measure_source_charts(const TriMesh& mesh, std::span<const float> source_uv,
                                          std::span<const uint32_t> partition_charts, uint32_t image_w,
                                          uint32_t image_h, double tau) {
  SourceChartMeasures m;
  const std::vector<uint32_t> charts = source_charts(mesh, source_uv);
  if (charts.empty()) return m;
  m.charts = *std::max_element(charts.begin(), charts.end()) + 1;
  const std::vector<uint32_t> opp = build_opposite_corners(mesh, build_vertex_faces(mesh));
  m.seam_edges = seam_edges_between(opp, charts);
  m.bound_seam_edges = seam_edges_between(opp, partition_charts);
  // solve_patch's validation alone (no iteration) says whether a face set is a disc.
  std::vector<std::vector<uint32_t>> chart_faces(m.charts);
  for (uint32_t f = 0; f < charts.size(); ++f) chart_faces[charts[f]].push_back(f);
  std::vector<Vec2> positions(mesh.vertex_count());
  SolveScratch scratch;
  double non_disc = 0, total = 0;
  for (const std::vector<uint32_t>& faces : chart_faces) {
    double area = 0;
    for (const uint32_t f : faces) area += face_area3(mesh, f);
    total += area;
    if (solve_patch(mesh, faces, SolveParams{0, 0, 0, false}, positions, scratch) == SolveStatus::ok)
      continue;
    ++m.non_disc_charts;
    non_disc += area;
  }
  m.non_disc_area = total > 0 ? non_disc / total : 0.0;
  if (image_w > 0 && image_h > 0) {
    std::vector<double> texels(source_uv.size());
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = double(source_uv[i]) * (i % 2 ? image_h : image_w);
    m.area_beyond_tau = area_beyond_tau_at_own_scale(mesh, charts, texels, tau);
  }
  return m;
}

}  // namespace gltfwarp
