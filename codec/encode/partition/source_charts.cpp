// Source UV charts, cut at the seams the texture shows (see source_charts.h).
#include "codec/encode/partition/source_charts.h"

#include <algorithm>

#include "codec/core/layout_report.h"
#include "codec/core/topology.h"
#include "codec/encode/partition/chart_split.h"

namespace gltfwarp {

std::vector<uint32_t> source_charts(const TriMesh& mesh, std::span<const float> source_uv,
                                    const SeamTest& seamless, const SeamTest& slit_crossable) {
  const uint32_t nf = mesh.face_count();
  if (source_uv.size() != size_t{nf} * 6) return std::vector<uint32_t>(nf, 0);
  const VertexFaces vf = build_vertex_faces(mesh);
  const std::vector<uint32_t> opp = build_opposite_corners(mesh, vf);
  // The source UV of face f at vertex v (v is a corner of f).
  auto uv_at = [&](uint32_t f, uint32_t v) {
    const uint32_t* t = &mesh.indices[3 * size_t{f}];
    const size_t c = 3 * size_t{f} + (t[0] == v ? 0 : t[1] == v ? 1 : 2);
    return Uv{source_uv[2 * c], source_uv[2 * c + 1]};
  };
  std::vector<uint8_t> edge(opp.size(), kEdgeOpen);
  for (size_t c = 0; c < opp.size(); ++c) {
    const uint32_t o = opp[c];
    if (o == kNone) continue;
    if (o < c) {
      edge[c] = edge[o];
      continue;
    }
    const uint32_t f = uint32_t(c / 3), g = o / 3;
    const uint32_t k = uint32_t(c % 3);
    const uint32_t va = mesh.indices[3 * size_t{f} + (k + 1) % 3],
                   vb = mesh.indices[3 * size_t{f} + (k + 2) % 3];
    const Uv fa = uv_at(f, va), fb = uv_at(f, vb), ga = uv_at(g, va), gb = uv_at(g, vb);
    if ((fa == ga && fb == gb) || (seamless && seamless(fa, fb, ga, gb)))
      edge[c] = kEdgeJoined;
    else
      edge[c] = slit_crossable && !slit_crossable(fa, fb, ga, gb) ? kEdgeCut : kEdgeShown;
  }
  // Charts grow breadth-first across joined edges, from the lowest face not
  // yet in one. With `cut`, a face whose cut seam has a face of the growing
  // chart on its other side stays out, and starts or joins a later chart: a
  // chart with such a slit (a cylinder's, a cube net's unjoined edges) would
  // let a patch cross it, and the viewer would blend the two sides'
  // unrelated colours there (MultiUVTest's cube: 6 of its 12 edges crossed,
  // each face's colour bled over its neighbour's, 46 dB surface PSNR).
  const auto grow = [&](bool cut) {
    std::vector<uint32_t> chart(nf, kNone), queue;
    const auto cut_from = [&](uint32_t g, uint32_t id) {
      for (uint32_t k = 0; k < 3; ++k) {
        const size_t c = 3 * size_t{g} + k;
        if (edge[c] == kEdgeCut && chart[opp[c] / 3] == id) return true;
      }
      return false;
    };
    uint32_t next = 0;
    for (uint32_t seed = 0; seed < nf; ++seed) {
      if (chart[seed] != kNone) continue;
      const uint32_t id = next++;
      chart[seed] = id;
      queue.assign(1, seed);
      for (size_t q = 0; q < queue.size(); ++q) {
        const uint32_t f = queue[q];
        for (uint32_t k = 0; k < 3; ++k) {
          const size_t c = 3 * size_t{f} + k;
          if (edge[c] != kEdgeJoined) continue;
          const uint32_t g = opp[c] / 3;
          if (chart[g] != kNone || (cut && cut_from(g, id))) continue;
          chart[g] = id;
          queue.push_back(g);
        }
      }
    }
    return chart;
  };
  const std::vector<uint32_t> whole = grow(false);
  if (!slit_crossable || std::find(edge.begin(), edge.end(), kEdgeCut) == edge.end()) return whole;
  const uint32_t whole_count = *std::max_element(whole.begin(), whole.end()) + 1;
  std::vector<double> whole_area(whole_count, 0.0), slit_length(whole_count, 0.0);
  for (uint32_t f = 0; f < nf; ++f) whole_area[whole[f]] += face_area3(mesh, f);
  for (size_t c = 0; c < edge.size(); ++c)
    if (edge[c] == kEdgeCut && opp[c] > c && whole[c / 3] == whole[opp[c] / 3])
      slit_length[whole[c / 3]] += opposite_edge_length(mesh, c);
  // A split is kept only where it cuts every slit, where every part holds
  // at least kMinPartShare of the chart's 3D area, and where the seams it
  // adds (joined edges between parts) are at most kMaxSeamPerSlit times as
  // long as the slits it cuts. Parts smaller than that are slivers whose
  // gutters and MIP blocks take their neighbours' colours; seams cost gutter
  // texels and resampling error along their length. Measured: the Fox's one
  // chart adds 5.8 times its 11 slits' length (1024-px render +1.7 dB at 2%
  // fewer bytes); the truck's body adds 44 times its one short slit (5.5%
  // more atlas bytes at fixed density for +0.5 dB surface).
  constexpr double kMinPartShare = 0.03, kMaxSeamPerSlit = 8.0;
  const auto acceptable = [&](const std::vector<uint32_t>& parts) {
    const uint32_t part_count = *std::max_element(parts.begin(), parts.end()) + 1;
    std::vector<double> part_area(part_count, 0.0), seam_length(whole_count, 0.0);
    for (uint32_t f = 0; f < nf; ++f) part_area[parts[f]] += face_area3(mesh, f);
    std::vector<uint8_t> ok(whole_count, 1);
    for (uint32_t f = 0; f < nf; ++f) {
      if (!(part_area[parts[f]] >= kMinPartShare * whole_area[whole[f]])) ok[whole[f]] = 0;
      for (uint32_t k = 0; k < 3; ++k) {
        const size_t c = 3 * size_t{f} + k;
        if (edge[c] == kEdgeCut && parts[opp[c] / 3] == parts[f]) ok[whole[f]] = 0;
        if (edge[c] == kEdgeJoined && opp[c] > c && parts[opp[c] / 3] != parts[f])
          seam_length[whole[f]] += opposite_edge_length(mesh, c);
      }
    }
    for (uint32_t w = 0; w < whole_count; ++w)
      if (!(seam_length[w] <= kMaxSeamPerSlit * slit_length[w])) ok[w] = 0;
    return ok;
  };
  // First, parts that refuse the faces across a cut seam: a cube net's
  // parts are half a face or more. Around a tube's slit, breadth-first
  // growth leaves the far side as a strip one face wide (the Fox's chart
  // came apart in 17 parts); such charts get a second try, from both sides.
  const std::vector<uint32_t> refused = grow(true);
  const std::vector<uint8_t> refused_ok = acceptable(refused);
  std::vector<uint8_t> retry(whole_count, 0);
  bool any_retry = false;
  for (uint32_t w = 0; w < whole_count; ++w) {
    retry[w] = slit_length[w] > 0 && !refused_ok[w];
    any_retry = any_retry || retry[w];
  }
  std::vector<uint32_t> sides;
  std::vector<uint8_t> sides_ok(whole_count, 0);
  if (any_retry) {
    sides = absorb_small_parts(mesh, opp, edge, whole, whole_area,
                               grow_from_slit_sides(mesh, opp, edge, whole, retry), kMinPartShare);
    sides_ok = acceptable(sides);
  }
  // Refused-growth parts, else two-sided parts, else the whole chart;
  // numbered by lowest face.
  const uint32_t refused_count = *std::max_element(refused.begin(), refused.end()) + 1;
  const uint32_t sides_count = sides.empty() ? 0 : *std::max_element(sides.begin(), sides.end()) + 1;
  std::vector<uint32_t> chart(nf), id_of_whole(whole_count, kNone), id_of_refused(refused_count, kNone),
      id_of_side(sides_count, kNone);
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t w = whole[f];
    uint32_t& id = refused_ok[w]             ? id_of_refused[refused[f]]
                   : retry[w] && sides_ok[w] ? id_of_side[sides[f]]
                                             : id_of_whole[w];
    if (id == kNone) id = next++;
    chart[f] = id;
  }
  return chart;
}

}  // namespace gltfwarp
