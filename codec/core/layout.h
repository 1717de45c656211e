// The shared layout replay: patch-local 2D positions for every corner, from
// the mesh and the partition alone. Encoder and decoder both run this one
// function on the same decoded mesh, so they cannot disagree (DESIGN.md,
// "The rule that makes the format work"). No threshold, no floating-point
// comparison decides anything here; the order is derived from connectivity.
//
// Replay semantics (normative; spec/ describes the same steps):
//  * Validation, in this order: positions and indices come in whole triples
//    and every index names a vertex (else bad_mesh); patch_of_face has one
//    entry per face, every entry is < patch_count and every patch has a face
//    (else bad_patch_id); scanning faces in ascending order, the patch ids
//    appear for the first time in the order 0, 1, 2, ... (else patch_order).
//  * Patches are numbered 0..P-1 in order of their lowest face index. The
//    seed of a patch is its lowest face, or seeds[p] when a seed list is
//    given (format 1.1: one face per patch, which must belong to that patch,
//    else bad_seed). Patches are laid out independently.
//  * Lengths: L(u, w) = sqrt(dx*dx + dy*dy + dz*dz) with d = pos[u] - pos[w]
//    (each float coordinate converted to double first), summed in that order.
//  * The seed face (v0, v1, v2) is placed rigidly: v0 at the origin; v1 (if
//    it differs from v0) at (L01, 0); v2 (if it differs from both) at
//    x = (L01^2 + L02^2 - L12^2) / (2 L01), y = sqrt(max(L02^2 - x^2, 0)),
//    or at (0, L02) when L01 == 0. If v1 == v0, v2 goes to (L02, 0).
//  * Then rounds. At the start of a round, the candidate list is the sorted
//    set of unplaced vertices q that have at least one face of the patch
//    that contains q exactly once and whose other two vertices are placed.
//    Candidates are processed in ascending vertex id. Each q is placed from
//    the faces of the patch that contain q exactly once and whose other two
//    vertices are placed at that moment (so vertices placed earlier in the
//    same round count), in ascending face id (place_vertex below). The round
//    ends when its list is done; the replay ends when a round's list is empty.
//  * Every face's three vertices must end up placed, otherwise the partition
//    is invalid (LayoutStatus::unreachable_face).
//  * Placement of q from faces i = 1..n, each written (q, a_i, b_i) in the
//    face's cyclic order starting at q, with 2D positions A_i, B_i, and
//    la = L(q, a), lb = L(q, b), lab2 = L(a, b)^2:
//      unfolding (the 3D triangle, scaled onto the placed edge, on its left):
//        if lab2 > 0: s = (la^2 - lb^2 + lab2) / (2 lab2),
//                     t = sqrt(max(la^2 / lab2 - s^2, 0)),
//                     U = A + s (B - A) + t perp(B - A), perp(x, y) = (-y, x)
//        else:        U = (A + B) / 2
//      weight (1 when the placed edge kept its 3D length, less otherwise):
//        d = |B - A|, e = 2 d sqrt(lab2) / (d^2 + lab2) (e = 1 if d^2 + lab2
//        == 0), w = e * e
//      start: p = sum w_i U_i / sum w_i, accumulated in face order, or the
//        plain mean of the U_i when sum w_i == 0;
//      relaxation, kRelaxSteps times (stress majorization of the edges q-a_i,
//        q-b_i with weights 1 / l^2): over the edges (A_i, la_i), (B_i, lb_i)
//        in face order, skipping edges with l == 0 or r = |p - X| == 0,
//        p' = sum (1/l^2) (X + (l / r) (p - X)) / sum (1/l^2); p = p' unless
//        no edge was used.
//    Every expression is evaluated left to right as written (codec/core/layout.cpp
//    is the reference), each sum accumulated from 0 in the order stated.
//    The comparisons with 0 above and the max() are the only float
//    comparisons; they guard divisions and square roots of rounded values.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/geometry2d.h"
#include "codec/core/layout_solve.h"
#include "codec/core/mesh.h"

namespace gltfwarp {

enum class LayoutStatus : uint8_t {
  ok = 0,
  bad_patch_id,      // a face names a patch >= patch_count, or a patch has no face
  patch_order,       // patches are not numbered in order of their lowest face
  unreachable_face,  // a face of a patch is never reached by the replay
  bad_mesh,          // an index is out of range
  bad_seed,          // a seed list of the wrong size, or a seed outside its patch
  bad_method,        // a method list of the wrong size, or an unknown method
  not_disc,          // a patch laid out by solve is not a topological disc (layout_solve.h)
};

// How a patch is laid out (format 1.2): the replay above, or layout_solve.h.
enum class LayoutMethod : uint8_t { unfold = 0, solve = 1 };
const char* to_string(LayoutStatus s);

// corner_xy receives 2 doubles per corner (6 per face): the patch-local
// position of that corner's vertex in model units. seeds: empty (every patch
// grows from its lowest face) or one face per patch. methods: empty (every
// patch unfolds) or one LayoutMethod per patch (format 1.2); a solve patch
// ignores its seed and is laid out by solve_patch with `solve`.
// threads: at most this many threads replay ranges of patches (0: one per
// core); meshes under 2^15 faces per thread use fewer. The bits do not depend on it.
LayoutStatus layout_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                            uint32_t patch_count, std::vector<double>& corner_xy,
                            std::span<const uint32_t> seeds = {}, std::span<const uint8_t> methods = {},
                            const SolveParams& solve = {}, uint32_t threads = 0);

// The same replay, handing over each face's three corner positions instead of
// storing them: sink(context, patch, face, xy) is called for each face of a
// patch (ascending face id) once the patch is fully placed. On a large mesh,
// ranges of patches replay on several threads, so the sink is called from
// several threads at once, never twice for one face, with patches in no fixed
// order; the positions are the same bits as one thread's. On an error some
// faces may already have been handed over.
using FaceSink = void (*)(void* context, uint32_t patch, uint32_t face, const Vec2 xy[3]);
LayoutStatus layout_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                            uint32_t patch_count, FaceSink sink, void* context,
                            std::span<const uint32_t> seeds = {}, std::span<const uint8_t> methods = {},
                            const SolveParams& solve = {}, uint32_t threads = 0);

// The faces of each patch in ascending order, by a counting sort: patch p's
// faces are faces[start[p] .. start[p + 1]). Every id must be < patch_count.
void faces_by_patch(std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                    std::vector<uint32_t>& start, std::vector<uint32_t>& faces);

// Building blocks of the replay, exposed so that the encoder's growth
// (codec/encode/partition/embed.cpp) computes exactly the same floats for the same inputs.
inline constexpr int kRelaxSteps = 2;

inline double length3_sq(const TriMesh& m, uint32_t u, uint32_t w) {
  const float* p = m.positions.data();
  const double dx = double(p[3 * u]) - double(p[3 * w]);
  const double dy = double(p[3 * u + 1]) - double(p[3 * w + 1]);
  const double dz = double(p[3 * u + 2]) - double(p[3 * w + 2]);
  return dx * dx + dy * dy + dz * dz;
}

// One face used to place q: the placed edge (A, B) and q's 3D distances.
struct Unfolding {
  Vec2 a, b;
  double la = 0, lb = 0, lab2 = 0;
};
inline Unfolding make_unfolding(const TriMesh& m, uint32_t q, uint32_t va, uint32_t vb, Vec2 a, Vec2 b) {
  Unfolding u;
  u.a = a;
  u.b = b;
  u.la = std::sqrt(length3_sq(m, q, va));
  u.lb = std::sqrt(length3_sq(m, q, vb));
  u.lab2 = length3_sq(m, va, vb);
  return u;
}

// The placement rule above (unfolding, weighted average, relaxation).
Vec2 place_vertex(std::span<const Unfolding> faces);

// The seed rule above: positions of the seed face's three corners.
void place_seed(const TriMesh& m, uint32_t face, Vec2 out[3]);

}  // namespace gltfwarp
