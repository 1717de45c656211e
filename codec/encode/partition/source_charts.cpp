// Source UV charts, cut at the seams the texture shows (see source_charts.h).
#include "codec/encode/partition/source_charts.h"

#include <algorithm>

#include "codec/core/layout_report.h"
#include "codec/core/topology.h"

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
  // Per corner, the edge opposite it: no neighbour, joined (the same UVs
  // on both sides, or a seam the texture hides), a seam it shows, or one
  // that must have two charts on its sides (slit_crossable refuses it).
  enum : uint8_t { kOpen, kJoined, kShown, kCut };
  std::vector<uint8_t> edge(opp.size(), kOpen);
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
      edge[c] = kJoined;
    else
      edge[c] = slit_crossable && !slit_crossable(fa, fb, ga, gb) ? kCut : kShown;
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
        if (edge[c] == kCut && chart[opp[c] / 3] == id) return true;
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
          if (edge[c] != kJoined) continue;
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
  if (!slit_crossable || std::find(edge.begin(), edge.end(), kCut) == edge.end()) return whole;
  // A split is kept only where every part holds at least kMinPartShare of
  // its chart's 3D area. Breadth-first growth can leave the far side of a
  // slit as a strip one face wide (the Fox's body chart came apart in 17
  // parts); as patches, strips are slivers whose gutters and MIP blocks take
  // their neighbours' colours. A cube net's parts are half a face or more.
  constexpr double kMinPartShare = 0.05;
  const std::vector<uint32_t> parts = grow(true);
  const uint32_t whole_count = *std::max_element(whole.begin(), whole.end()) + 1;
  const uint32_t part_count = *std::max_element(parts.begin(), parts.end()) + 1;
  std::vector<double> whole_area(whole_count, 0.0), part_area(part_count, 0.0);
  for (uint32_t f = 0; f < nf; ++f) {
    const double a = face_area3(mesh, f);
    whole_area[whole[f]] += a;
    part_area[parts[f]] += a;
  }
  std::vector<uint8_t> split(whole_count, 1);
  for (uint32_t f = 0; f < nf; ++f)
    if (!(part_area[parts[f]] >= kMinPartShare * whole_area[whole[f]])) split[whole[f]] = 0;
  // Parts of split charts, whole charts elsewhere, numbered by lowest face.
  std::vector<uint32_t> chart(nf), id_of_part(part_count, kNone), id_of_whole(whole_count, kNone);
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    uint32_t& id = split[whole[f]] ? id_of_part[parts[f]] : id_of_whole[whole[f]];
    if (id == kNone) id = next++;
    chart[f] = id;
  }
  return chart;
}

}  // namespace gltfwarp
