#include "codec/encode/partition/notch_moves.h"

#include <algorithm>

#include "codec/core/topology.h"

namespace gltfwarp {

void notch_moves(std::span<const uint32_t> opposite, std::span<const uint32_t> patch_of_face,
                 std::vector<NotchMove>& moves, std::vector<NotchGroup>& groups) {
  moves.clear();
  groups.clear();
  const uint32_t nf = static_cast<uint32_t>(patch_of_face.size());
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t a = patch_of_face[f];
    if (a == kNone) continue;
    uint32_t nb[3], n = 0;
    for (int k = 0; k < 3; ++k) {
      const uint32_t o = opposite[3 * size_t{f} + k];
      if (o != kNone && patch_of_face[o / 3] != a) nb[n++] = patch_of_face[o / 3];
    }
    uint32_t b = kNone;
    if (n >= 2 && nb[0] == nb[1])
      b = nb[0];
    else if (n == 3 && (nb[0] == nb[2] || nb[1] == nb[2]))
      b = nb[2];
    if (b != kNone) moves.push_back({a, b, f});
  }
  std::stable_sort(moves.begin(), moves.end(),
                   [](const NotchMove& l, const NotchMove& r) { return l.a != r.a ? l.a < r.a : l.b < r.b; });
  for (size_t i = 0; i < moves.size();) {
    size_t j = i;
    while (j < moves.size() && moves[j].a == moves[i].a && moves[j].b == moves[i].b) ++j;
    groups.push_back({i, j});
    i = j;
  }
  // Most faces first: a pass's budget goes where the seams shrink most.
  std::stable_sort(groups.begin(), groups.end(), [](const NotchGroup& l, const NotchGroup& r) {
    return l.end - l.begin > r.end - r.begin;
  });
}

}  // namespace gltfwarp
