// The solve layout method (codec/core/layout_solve.h, format 1.2): disc
// patches of generated shapes come out unflipped and within tau, non-disc
// patches are rejected, and with solve merges the encoder's positions equal
// the decoder's bit for bit, through the bitstream too.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "codec/core/distortion.h"
#include "codec/core/layout.h"
#include "codec/core/layout_report.h"
#include "codec/core/topology.h"
#include "codec/encode/partition/embed.h"
#include "codec/encode/partition/solve_merge.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "tests/support/testing/shapes.h"

namespace gltfwarp {
namespace {

// Faces within `rounds` edge-adjacency steps of `start`, ascending.
std::vector<uint32_t> face_ball(const TriMesh& m, uint32_t start, int rounds) {
  const VertexFaces vf = build_vertex_faces(m);
  const std::vector<uint32_t> opp = build_opposite_corners(m, vf);
  std::vector<uint8_t> in(m.face_count(), 0);
  std::vector<uint32_t> ball = {start}, front = {start}, next;
  in[start] = 1;
  for (int r = 0; r < rounds; ++r) {
    next.clear();
    for (uint32_t f : front)
      for (int k = 0; k < 3; ++k) {
        const uint32_t o = opp[3 * f + k];
        if (o == kNone || in[o / 3]) continue;
        in[o / 3] = 1;
        next.push_back(o / 3);
        ball.push_back(o / 3);
      }
    front.swap(next);
  }
  std::sort(ball.begin(), ball.end());
  return ball;
}

std::vector<double> solve_xy(const TriMesh& m, std::span<const uint32_t> faces, SolveStatus& status,
                             const SolveParams& params = SolveParams{}) {
  std::vector<Vec2> pos(m.vertex_count());
  SolveScratch s;
  status = solve_patch(m, faces, params, pos, s);
  std::vector<double> xy(size_t{m.face_count()} * 6, 0.0);
  for (uint32_t f : faces)
    for (int k = 0; k < 3; ++k) {
      xy[6 * f + 2 * k] = pos[m.indices[3 * f + k]].x;
      xy[6 * f + 2 * k + 1] = pos[m.indices[3 * f + k]].y;
    }
  return xy;
}

TEST(LayoutSolve, CirclePointsAreExactAtTheStartAndTurnOnce) {
  const Vec2 o = solve_circle_point(0.0, 2.0);
  EXPECT_EQ(o.x, 0.0);
  EXPECT_EQ(o.y, 0.0);
  // Quarter turns land near (-r, r), (-2r, 0), (-r, -r); the angle grows monotonically.
  const Vec2 q = solve_circle_point(0.25, 1.0), h = solve_circle_point(0.5, 1.0);
  EXPECT_NEAR(q.x, -1.0, 1e-4);
  EXPECT_NEAR(q.y, 1.0, 1e-4);
  EXPECT_NEAR(h.x, -2.0, 1e-4);
  EXPECT_NEAR(h.y, 0.0, 1e-4);
  Vec2 prev = solve_circle_point(0.001, 1.0);
  for (int i = 2; i < 1000; ++i) {
    const Vec2 p = solve_circle_point(i / 1000.0, 1.0);
    EXPECT_GT(orient2d_sign({-1.0, 0.0}, prev, p), 0) << i;  // counter-clockwise about the centre
    prev = p;
  }
}

// With the solve the encoder asks for (cotangent ARAP, format 1.4): 1.2's
// uniform weights leave one face of a twisted-cone ball at 0.57 of its 3D
// area, which the encoder's rule (face_within_tau) turns down.
TEST(LayoutSolve, DiscPatchesOfShapesAreUnflippedAndWithinTau) {
  const double tau = 1.3;
  int solved = 0;
  for (const char* name : {"sphere", "torus", "twisted_cone", "bumpy_sphere", "plane"}) {
    ShapeMesh sm;
    const std::string n = name;
    if (n == "sphere") sm = make_sphere(48, 24);
    if (n == "torus") sm = make_torus(64, 32);
    if (n == "twisted_cone") sm = make_twisted_cone(48, 24);
    if (n == "bumpy_sphere") sm = make_bumpy_sphere(64, 32);
    if (n == "plane") sm = make_plane(20, 20);
    const TriMesh& m = sm.mesh;
    for (uint32_t start : {m.face_count() / 3, m.face_count() / 2 + 7}) {
      const std::vector<uint32_t> ball = face_ball(m, start, 5);
      SolveStatus st;
      const std::vector<double> xy = solve_xy(m, ball, st, kEncoderSolveParams);
      ASSERT_EQ(st, SolveStatus::ok) << name << " ball at " << start;
      for (uint32_t f : ball) {
        const double* c = &xy[6 * f];
        const Vec2 P[3] = {{c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]}};
        EXPECT_GT(orient2d_sign(P[0], P[1], P[2]), 0) << name << " face " << f;
        EXPECT_LE(face_distortion(m, f, P), tau) << name << " face " << f;
      }
      EXPECT_TRUE(solved_patch_acceptable(m, ball, xy, tau)) << name;
      ++solved;
    }
  }
  EXPECT_EQ(solved, 10);
}

TEST(LayoutSolve, NonDiscPatchesAreRejected) {
  std::vector<uint32_t> all;
  const ShapeMesh sphere = make_sphere(16, 8);  // closed: no boundary loop
  for (uint32_t f = 0; f < sphere.mesh.face_count(); ++f) all.push_back(f);
  SolveStatus st;
  solve_xy(sphere.mesh, all, st);
  EXPECT_EQ(st, SolveStatus::not_disc);
  const ShapeMesh tube = make_cylinder_open(16, 4);  // an annulus: two loops
  all.clear();
  for (uint32_t f = 0; f < tube.mesh.face_count(); ++f) all.push_back(f);
  solve_xy(tube.mesh, all, st);
  EXPECT_EQ(st, SolveStatus::not_disc);
  // Through the replay: a solve method on the closed sphere is not_disc.
  std::vector<uint32_t> pof(sphere.mesh.face_count(), 0);
  std::vector<double> xy;
  const std::vector<uint8_t> solve = {uint8_t(LayoutMethod::solve)}, bad = {2};
  EXPECT_EQ(layout_patches(sphere.mesh, pof, 1, xy, {}, solve), LayoutStatus::not_disc);
  EXPECT_EQ(layout_patches(sphere.mesh, pof, 1, xy, {}, bad), LayoutStatus::bad_method);
  const std::vector<uint8_t> two = {0, 1};
  EXPECT_EQ(layout_patches(sphere.mesh, pof, 1, xy, {}, two), LayoutStatus::bad_method);
}

// With solve merges on, every generated shape keeps the embedding's
// guarantees; solve patches appear; the encoder's positions are the
// decoder's, bit for bit, also after a trip through the bitstream.
TEST(LayoutSolve, MixedEmbeddingOnShapesMatchesTheDecoder) {
  size_t solve_patches = 0;
  for (const NamedShape& ns : standard_shapes(1500)) {
    const TriMesh& m = ns.shape.mesh;
    EmbedOptions eo;
    eo.solve_merge = true;
    const Embedding e = embed(m, eo);
    ASSERT_EQ(e.status, LayoutStatus::ok) << ns.name;
    EXPECT_EQ(e.report.flipped, 0u) << ns.name;
    EXPECT_EQ(e.report.over_tau, 0u) << ns.name;
    EXPECT_EQ(e.report.shrunk, 0u) << ns.name;
    ASSERT_EQ(e.corner_xy.size(), e.encoder_xy.size());
    EXPECT_EQ(std::memcmp(e.corner_xy.data(), e.encoder_xy.data(), e.corner_xy.size() * sizeof(double)), 0)
        << ns.name;
    if (e.methods.empty()) continue;
    ASSERT_EQ(e.methods.size(), e.patch_count);
    for (uint32_t p = 0; p < e.patch_count; ++p) solve_patches += e.methods[p];
    // Through the stream: the decoded map lays out the same bits.
    UvMap map;
    map.texel_scale = 64.0f;
    map.atlas_width = map.atlas_height = 1024;
    map.patch_count = e.patch_count;
    map.patch_of_face = e.patch_of_face;
    map.seeds = e.seeds;
    map.methods = e.methods;
    map.solve = e.solve;
    map.placements.assign(e.patch_count, PatchPlacement{});
    const std::vector<uint8_t> bytes = write_uvmap(map, m);
    // The encoder's solve runs on cotangent weights, which only 1.4 expresses.
    EXPECT_TRUE(map.solve.cotangent_weights);
    EXPECT_EQ(bytes[5], 4) << "a stream with a cotangent-weighted solve patch is version 1.4";
    UvMap back;
    ASSERT_EQ(read_uvmap(bytes, m, back), UvStatus::ok);
    EXPECT_EQ(back, map);
    std::vector<double> xy;
    ASSERT_EQ(
        layout_patches(m, back.patch_of_face, back.patch_count, xy, back.seeds, back.methods, back.solve),
        LayoutStatus::ok);
    EXPECT_EQ(std::memcmp(xy.data(), e.corner_xy.data(), xy.size() * sizeof(double)), 0) << ns.name;
  }
  EXPECT_GT(solve_patches, 0u);
}

// A face of the left half that pokes into the right half (two of its edges
// on it) goes back: one seam edge fewer, both patches solved and acceptable.
// The union is over max_faces, so only a move can straighten the seam.
TEST(LayoutSolve, SolveMergesMoveNotchFacesAcrossTheSeam) {
  const TriMesh m = make_plane(8, 8).mesh;
  const uint32_t nf = m.face_count();
  const std::vector<uint32_t> opp = build_opposite_corners(m, build_vertex_faces(m));
  std::vector<uint32_t> patch_of(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    double cx = 0;
    for (int k = 0; k < 3; ++k) cx += m.positions[3 * size_t{m.indices[3 * f + k]}];
    patch_of[f] = cx / 3 < 0.5 ? 0 : 1;
  }
  uint32_t notch = kNone;
  for (uint32_t f = 0; f < nf && notch == kNone; ++f) {
    if (patch_of[f] != 1) continue;
    int on_left = 0, on_right = 0;
    for (int k = 0; k < 3; ++k) {
      const uint32_t o = opp[3 * f + k];
      if (o != kNone) ++(patch_of[o / 3] == 0 ? on_left : on_right);
    }
    if (on_left == 1 && on_right == 2) notch = f;
  }
  ASSERT_NE(notch, kNone);
  patch_of[notch] = 0;
  std::vector<std::vector<uint32_t>> patches(2);
  for (uint32_t f = 0; f < nf; ++f) patches[patch_of[f]].push_back(f);
  std::vector<double> xy;
  ASSERT_EQ(layout_patches(m, patch_of, 2, xy), LayoutStatus::ok);
  const uint32_t seams_before = measure_embedding(m, patch_of, 2, xy).seam_edges;
  std::vector<uint8_t> method;
  SolveMergeOptions so;
  so.max_faces = nf - 8;
  const JoinRule any = [](std::span<const uint32_t>, std::span<const uint32_t>) { return true; };
  EXPECT_EQ(solve_merge(m, opp, patches, xy, method, so, any), 1u);  // no merge, one face moved
  ASSERT_EQ(patches.size(), 2u);
  EXPECT_TRUE(std::binary_search(patches[1].begin(), patches[1].end(), notch));
  for (uint32_t p = 0; p < 2; ++p)
    for (uint32_t f : patches[p]) patch_of[f] = p;
  EXPECT_LT(measure_embedding(m, patch_of, 2, xy).seam_edges, seams_before);
  for (uint32_t p = 0; p < 2; ++p) {
    EXPECT_EQ(method[p], uint8_t(LayoutMethod::solve));
    EXPECT_TRUE(std::is_sorted(patches[p].begin(), patches[p].end()));
    EXPECT_TRUE(solved_patch_acceptable(m, patches[p], xy, so.tau));
  }
}

TEST(LayoutSolve, UnfoldOnlyMapsKeepTheirOlderVersion) {
  const ShapeMesh sm = make_sphere(24, 12);
  EmbedOptions eo;
  const Embedding e = embed(sm.mesh, eo);
  ASSERT_EQ(e.status, LayoutStatus::ok);
  EXPECT_TRUE(e.methods.empty());
  UvMap map;
  map.texel_scale = 64.0f;
  map.atlas_width = map.atlas_height = 512;
  map.patch_count = e.patch_count;
  map.patch_of_face = e.patch_of_face;
  map.seeds = e.seeds;
  map.placements.assign(e.patch_count, PatchPlacement{});
  const std::vector<uint8_t> plain = write_uvmap(map, sm.mesh);
  map.methods.assign(e.patch_count, uint8_t(LayoutMethod::unfold));
  map.solve.tutte_iterations = 5;
  EXPECT_EQ(write_uvmap(map, sm.mesh), plain) << "all-unfold methods write the 1.0/1.1 stream";
  EXPECT_LE(plain[5], 1);
}

}  // namespace
}  // namespace gltfwarp
