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
    if (fa == ga && fb == gb)
      edge[c] = kEdgeJoined;
    else if (seamless && seamless(fa, fb, ga, gb))
      edge[c] = kEdgeHidden;
    else
      edge[c] = slit_crossable && !slit_crossable(fa, fb, ga, gb) ? kEdgeCut : kEdgeShown;
  }
  // Charts grow breadth-first across joined and hidden edges, from the
  // lowest face not yet in one; the source's own charts only across joined
  // ones. With kRefuseCut, a face whose cut seam has a face of the growing
  // chart on its other side stays out, and starts or joins a later chart: a
  // chart with such a slit (a cylinder's, a cube net's unjoined edges) would
  // let a patch cross it, and the viewer would blend the two sides'
  // unrelated colours there (MultiUVTest's cube: 6 of its 12 edges crossed,
  // each face's colour bled over its neighbour's, 46 dB surface PSNR).
  enum Growth { kWhole, kRefuseCut, kOwn, kOwnRefuseCut };
  const auto grow = [&](Growth how) {
    const bool own = how == kOwn || how == kOwnRefuseCut;
    const bool refuse = how == kRefuseCut || how == kOwnRefuseCut;
    return grow_components(nf, opp, [&](size_t c, uint32_t, uint32_t g, uint32_t id, const auto& chart) {
      if (own ? edge[c] != kEdgeJoined : !joins(edge[c])) return false;
      if (!refuse) return true;
      for (uint32_t k = 0; k < 3; ++k) {  // refused: a cut seam to this chart
        const size_t e = 3 * size_t{g} + k;
        if (edge[e] == kEdgeCut && chart[opp[e] / 3] == id) return false;
      }
      return true;
    });
  };
  const std::vector<uint32_t> whole = grow(kWhole);
  if (!slit_crossable || std::find(edge.begin(), edge.end(), kEdgeCut) == edge.end()) return whole;
  const uint32_t whole_count = *std::max_element(whole.begin(), whole.end()) + 1;
  std::vector<double> face_area(nf), whole_area(whole_count, 0.0), slit_length(whole_count, 0.0);
  for (uint32_t f = 0; f < nf; ++f) {
    face_area[f] = face_area3(mesh, f);
    whole_area[whole[f]] += face_area[f];
  }
  for (size_t c = 0; c < edge.size(); ++c)
    if (edge[c] == kEdgeCut && opp[c] > c && whole[c / 3] == whole[opp[c] / 3])
      slit_length[whole[c / 3]] += opposite_edge_length(mesh, c);
  // A split is kept only where it cuts every slit, where every part holds
  // at least kMinPartShare of the 3D area of the chart it came from (the
  // whole chart, or the source's own chart), and where the seams it adds
  // (joined and hidden edges between parts) are at most kMaxSeamPerSlit
  // times as long as the slits it cuts. Smaller parts are slivers whose
  // gutters and MIP blocks take their neighbours' colours; seams cost gutter
  // texels and resampling error along their length. Measured (default
  // encodes; surface, 1024-px and 256-px render dB):
  //  - the Fox's one chart (22 slit edges), split along its own charts
  //    (6.1 times the slits' length in seams): 90,964 B at 44.51 / 39.98 /
  //    33.74 -> 83,624 B at 44.18 / 41.57 / 34.65; at fixed density its
  //    atlas image 28.4 -> 24.9 KB at 45.63 -> 46.89 dB surface;
  //  - split by two fronts instead (6.1 times): 88,280 B at 44.00 / 41.47 /
  //    34.37;
  //  - the truck's body chart would add 23 to 320 times its one short slit
  //    (at 44 times: atlas +5.5% at fixed density for +0.5 dB surface).
  constexpr double kMinPartShare = 0.03, kMaxSeamPerSlit = 8.0;
  const auto acceptable = [&](const std::vector<uint32_t>& parts, const std::vector<uint32_t>& within) {
    const uint32_t part_count = *std::max_element(parts.begin(), parts.end()) + 1;
    const uint32_t within_count = *std::max_element(within.begin(), within.end()) + 1;
    std::vector<double> part_area(part_count, 0.0), within_area(within_count, 0.0),
        seam_length(whole_count, 0.0);
    for (uint32_t f = 0; f < nf; ++f) {
      part_area[parts[f]] += face_area[f];
      within_area[within[f]] += face_area[f];
    }
    std::vector<uint8_t> ok(whole_count, 1);
    for (uint32_t f = 0; f < nf; ++f) {
      if (!(part_area[parts[f]] >= kMinPartShare * within_area[within[f]])) ok[whole[f]] = 0;
      for (uint32_t k = 0; k < 3; ++k) {
        const size_t c = 3 * size_t{f} + k;
        if (edge[c] == kEdgeCut && parts[opp[c] / 3] == parts[f]) ok[whole[f]] = 0;
        if (joins(edge[c]) && opp[c] > c && parts[opp[c] / 3] != parts[f])
          seam_length[whole[f]] += opposite_edge_length(mesh, c);
      }
    }
    for (uint32_t w = 0; w < whole_count; ++w)
      if (!(seam_length[w] <= kMaxSeamPerSlit * slit_length[w])) ok[w] = 0;
    return ok;
  };
  // Ways to split, in order of preference; each chart with a slit takes the
  // first that splits it acceptably, else stays whole.
  //  - Parts that refuse the faces across a cut seam: a cube net's parts
  //    are half a face or more.
  //  - The source's own charts (its hidden seams not crossed), with any
  //    slit inside one refused as above: a chart joined across hidden seams
  //    whose slits the source's charts separate (the Fox's one chart, whose
  //    refused growth comes apart in 17 parts).
  //  - Parts grown from both sides of the slits at once (chart_split.h): a
  //    tube's slit, which refused growth leaves as a strip one face wide.
  std::vector<std::vector<uint32_t>> ways{grow(kRefuseCut), grow(kOwnRefuseCut)};
  std::vector<std::vector<uint8_t>> fits{acceptable(ways[0], whole), acceptable(ways[1], grow(kOwn))};
  std::vector<uint8_t> retry(whole_count, 0);
  bool any_retry = false;
  for (uint32_t w = 0; w < whole_count; ++w) {
    retry[w] = slit_length[w] > 0 && !fits[0][w] && !fits[1][w];
    any_retry = any_retry || retry[w];
  }
  if (any_retry) {
    ways.push_back(absorb_small_parts(mesh, opp, edge, whole, face_area, whole_area,
                                      grow_from_slit_sides(mesh, opp, edge, whole, retry), kMinPartShare));
    fits.push_back(acceptable(ways.back(), whole));
  }
  std::vector<uint32_t> way(whole_count, kNone);  // kNone: whole
  for (uint32_t w = 0; w < whole_count; ++w)
    for (uint32_t i = 0; i < ways.size() && way[w] == kNone; ++i)
      if (slit_length[w] > 0 && fits[i][w]) way[w] = i;
  // Numbered by lowest face.
  std::vector<std::vector<uint32_t>> id_of(ways.size());
  for (size_t i = 0; i < ways.size(); ++i)
    id_of[i].assign(*std::max_element(ways[i].begin(), ways[i].end()) + 1, kNone);
  std::vector<uint32_t> id_of_whole(whole_count, kNone), chart(nf);
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t w = whole[f];
    uint32_t& id = way[w] == kNone ? id_of_whole[w] : id_of[way[w]][ways[way[w]][f]];
    if (id == kNone) id = next++;
    chart[f] = id;
  }
  return chart;
}

}  // namespace gltfwarp
