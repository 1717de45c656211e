// The source's own UV charts on the embedding mesh: faces joined across every
// edge whose two faces carry the same source UVs at both ends. A patch that
// crosses a source UV seam puts texels of two unrelated source regions side
// by side, and the viewer's bilinear filter blends them along the seam; the
// partition keeps each patch inside one chart instead (EmbedOptions::face_chart).
// A seam with one chart on both sides (a slit: a cylinder's, the unjoined
// edges of a cube net) may cut that chart in two, so that no patch crosses
// it either.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "codec/core/mesh.h"

namespace gltfwarp {

using Uv = std::array<float, 2>;

// Whether the texture agrees across a source seam edge: the edge runs from
// a0 to a1 in one face's UVs and from b0 to b1 in the other's (a0 and b0 at
// the same vertex). A seam where it does is invisible to the viewer's
// filter, so a patch may cross it.
using SeamTest = std::function<bool(Uv a0, Uv a1, Uv b0, Uv b1)>;

// Chart id per face, numbered 0, 1, ... in order of each chart's lowest face.
// source_uv holds 2 floats per corner (6 per face); UVs compare bit for bit,
// as the source's shared vertices give equal floats and a seam does not.
// With `seamless`, faces also join across the seam edges it accepts. With
// `slit_crossable`, a chart holding both sides of a seam edge it refuses
// (and `seamless` too) is split so that every such edge lies between two
// parts. Three ways are tried in turn: parts that grow breadth-first from
// their lowest face and leave out a face across such a seam; the source's
// own charts (not joined across hidden seams), split the same way; and
// parts grown from both sides of the slits at once (a tube comes apart in
// halves; chart_split.h). A way is kept only where every part holds at
// least 3% of the chart's 3D area (of the source's own chart, for the
// second) and the seams it adds are at most 8 times as long as the slits it
// cuts; otherwise the chart stays whole. The encoder cuts only seams with a
// marked step (kSlitCrossable in seam_continuity.h). Without it, a chart
// may hold both sides of a seam.
// Requires valid indices (mesh_indices_valid).
std::vector<uint32_t> source_charts(const TriMesh& mesh, std::span<const float> source_uv,
                                    const SeamTest& seamless = nullptr,
                                    const SeamTest& slit_crossable = nullptr);

}  // namespace gltfwarp
