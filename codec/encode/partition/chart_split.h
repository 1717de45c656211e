// Splitting a source UV chart at its slits (source_charts.h): seams with one
// chart on both sides whose texture step the encoder refuses to let a patch
// cross. Breadth-first growth that refuses the faces across a slit leaves a
// tube's far side as single triangles; growing from both sides of the slits
// at once halves it instead.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "codec/core/mesh.h"
#include "codec/core/topology.h"

namespace gltfwarp {

// Per corner, the edge opposite it: no neighbour, joined (the same UVs on
// both sides), hidden (a seam the texture hides, which charts also join
// across), a seam it shows, or one that must have two charts on its sides
// (slit_crossable refuses it).
enum ChartEdge : uint8_t { kEdgeOpen, kEdgeJoined, kEdgeHidden, kEdgeShown, kEdgeCut };
inline bool joins(uint8_t edge) { return edge == kEdgeJoined || edge == kEdgeHidden; }

// Faces in components grown breadth-first, numbered by lowest face: from
// each face not yet in one, growth crosses the edge opposite corner c of a
// face f of component `id` into its neighbour g where
// crosses(c, f, g, id, comp) holds (comp: the components so far). `opp` is
// build_opposite_corners'.
template <class Crosses>
std::vector<uint32_t> grow_components(uint32_t face_count, std::span<const uint32_t> opp, Crosses crosses) {
  std::vector<uint32_t> comp(face_count, kNone), queue;
  for (uint32_t seed = 0, id = 0; seed < face_count; ++seed) {
    if (comp[seed] != kNone) continue;
    comp[seed] = id;
    queue.assign(1, seed);
    for (size_t q = 0; q < queue.size(); ++q) {
      const uint32_t f = queue[q];
      for (uint32_t k = 0; k < 3; ++k) {
        const size_t c = 3 * size_t{f} + k;
        if (opp[c] == kNone) continue;
        const uint32_t g = opp[c] / 3;
        if (comp[g] != kNone || !crosses(c, f, g, id, std::as_const(comp))) continue;
        comp[g] = id;
        queue.push_back(g);
      }
    }
    ++id;
  }
  return comp;
}

// The 3D length of the edge opposite corner c.
double opposite_edge_length(const TriMesh& mesh, size_t c);

// Parts of the charts marked in `retry` (chart ids per face in `whole`),
// grown from both sides of their slits at once, so that a tube cut along its
// length comes apart in two halves that meet opposite the slit. The cut
// edges of a chart form chains (trees, on a cube net); each chain is
// oriented along its length, and the faces on its left and on its right
// start one front each. The fronts grow breadth-first in step across joined
// edges; parts are the connected sets of faces one front reached. Faces of
// other charts form one part per chart. Numbered by lowest face. `opp` is
// build_opposite_corners' and `edge` holds a ChartEdge per corner.
std::vector<uint32_t> grow_from_slit_sides(const TriMesh& mesh, std::span<const uint32_t> opp,
                                           std::span<const uint8_t> edge, std::span<const uint32_t> whole,
                                           std::span<const uint8_t> retry);

// Merges each part below min_share of its chart's 3D area (face_area per
// face, whole_area per chart id) into the neighbouring part it shares the longest joined boundary
// with, where no cut edge lies between the two, until none can merge.
// Fronts racing around a chart with many slits leave scraps where they
// meet: the Fox's one chart comes out in 28 parts, 11 after merging.
// Renumbered by lowest face.
std::vector<uint32_t> absorb_small_parts(const TriMesh& mesh, std::span<const uint32_t> opp,
                                         std::span<const uint8_t> edge, std::span<const uint32_t> whole,
                                         std::span<const double> face_area,
                                         std::span<const double> whole_area, std::vector<uint32_t> part,
                                         double min_share);

}  // namespace gltfwarp
