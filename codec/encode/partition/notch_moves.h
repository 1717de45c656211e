// The faces that poke out of their patch into one neighbour (a notch, or a
// hole of one face): both seam-straightening passes (the compact
// partition's unfold moves in embed.cpp and the solve moves of
// solve_merge.h) move them across, one or three seam edges fewer each.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace gltfwarp {

struct NotchMove {
  uint32_t a, b, f;  // face f of patch a has two or three edges on patch b
};

// The faces of one (a, b) pair: moves[begin, end).
struct NotchGroup {
  size_t begin, end;
};

// opposite: the opposite corner of every corner (kNone on a boundary);
// patch_of_face: each face's patch. Fills moves (faces ascending within a
// pair, pairs by a then b) and groups (most faces first, ties by pair).
void notch_moves(std::span<const uint32_t> opposite, std::span<const uint32_t> patch_of_face,
                 std::vector<NotchMove>& moves, std::vector<NotchGroup>& groups);

}  // namespace gltfwarp
