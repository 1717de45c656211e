// The shared layout replay: patch-local 2D positions for every corner, from
// the mesh and the partition alone. Encoder and decoder both run this one
// function on the same decoded mesh, so they cannot disagree (DESIGN.md,
// "The rule that makes the format work"). No threshold, no floating-point
// comparison decides anything here; the order is derived from connectivity.
//
// Replay semantics (normative; spec/ describes the same steps):
//  * Patches are numbered 0..P-1 in order of their lowest face index; the
//    seed of a patch is its lowest face. patch_of_face[f] < patch_count.
//  * The seed face (v0, v1, v2) is placed rigidly: v0 at the origin, v1 on +x
//    at |v0v1|, v2 above the x axis with its true 3D distances.
//  * Then rounds. At the start of a round, the candidate list is the sorted
//    set of unplaced vertices q that have at least one face of the patch whose
//    other two vertices are placed. Candidates are processed in ascending
//    vertex id. Each q is placed from the faces of the patch that contain q
//    and whose other two vertices are placed at that moment (so vertices
//    placed earlier in the same round count), in ascending face id: the
//    weighted average of the unfoldings across those faces' placed edges,
//    then a fixed number of relaxation steps. The round ends when its list is
//    done; the replay ends when a round's list is empty.
//  * Every face's three vertices must end up placed, otherwise the partition
//    is invalid (LayoutStatus::unreachable_face).
// All arithmetic is IEEE double with + - * / and sqrt only (no libm
// transcendental functions, no FMA contraction), so it is bit-exact.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/mesh.h"

namespace gltfwarp {

enum class LayoutStatus : uint8_t {
  ok = 0,
  bad_patch_id,      // a face names a patch >= patch_count, or a patch has no face
  patch_order,       // patches are not numbered in order of their lowest face
  unreachable_face,  // a face of a patch is never reached by the replay
  bad_mesh,          // an index is out of range
};
const char* to_string(LayoutStatus s);

// corner_xy receives 2 doubles per corner (6 per face): the patch-local
// position of that corner's vertex in model units.
LayoutStatus layout_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                            uint32_t patch_count, std::vector<double>& corner_xy);

}  // namespace gltfwarp
