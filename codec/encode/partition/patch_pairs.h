// The pairs of patches that share edges, most shared edges first: the order
// in which both merge passes (the compact partition's unfold merges and the
// solve merges of solve_merge.h) try unions.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace gltfwarp {

struct PatchPair {
  uint32_t a, b;    // a < b
  uint32_t shared;  // interior edges between them
};

// opposite: the opposite corner of every corner (kNone on a boundary, as
// build_opposite_corners gives it); patch_of_face: each face's patch, kNone
// for a face in none. Pairs with equal counts keep the order of (a, b).
// `keys` is reused storage.
void adjacent_patch_pairs(std::span<const uint32_t> opposite, std::span<const uint32_t> patch_of_face,
                          std::vector<uint64_t>& keys, std::vector<PatchPair>& pairs);

}  // namespace gltfwarp
