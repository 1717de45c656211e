#include "codec/encode/partition/patch_pairs.h"

#include <algorithm>
#include <utility>

#include "codec/core/topology.h"

namespace gltfwarp {

void adjacent_patch_pairs(std::span<const uint32_t> opposite, std::span<const uint32_t> patch_of_face,
                          std::vector<uint64_t>& keys, std::vector<PatchPair>& pairs) {
  keys.clear();
  for (size_t c = 0; c < opposite.size(); ++c) {
    const uint32_t o = opposite[c];
    if (o == kNone || o < c) continue;
    uint32_t a = patch_of_face[c / 3], b = patch_of_face[o / 3];
    if (a == b || a == kNone || b == kNone) continue;
    if (a > b) std::swap(a, b);
    keys.push_back((uint64_t(a) << 32) | b);
  }
  std::sort(keys.begin(), keys.end());
  pairs.clear();
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    pairs.push_back({uint32_t(keys[i] >> 32), uint32_t(keys[i]), uint32_t(j - i)});
    i = j;
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const PatchPair& l, const PatchPair& r) { return l.shared > r.shared; });
}

}  // namespace gltfwarp
