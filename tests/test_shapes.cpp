// Generated models (tests/support/testing/shapes.h): well-formed buffers and the topology
// each shape is meant to have.
#include <gtest/gtest.h>

#include <cmath>

#include "codec/core/topology.h"
#include "tests/support/testing/shapes.h"

namespace gltfwarp {
namespace {

// V - E + F over unique undirected edges.
long euler_characteristic(const TriMesh& m) {
  const VertexFaces vf = build_vertex_faces(m);
  const std::vector<uint32_t> opp = build_opposite_corners(m, vf);
  size_t half = 0, paired = 0;
  for (size_t c = 0; c < opp.size(); ++c) {
    ++half;
    paired += opp[c] != kNone;
  }
  const long edges = long(half - paired) + long(paired / 2);
  return long(m.vertex_count()) - edges + long(m.face_count());
}

TEST(Shapes, BuffersAreWellFormed) {
  for (const NamedShape& s : standard_shapes(1500)) {
    SCOPED_TRACE(s.name);
    const TriMesh& m = s.shape.mesh;
    ASSERT_TRUE(mesh_indices_valid(m));
    ASSERT_GT(m.face_count(), 50u);
    ASSERT_EQ(s.shape.corner_uv.size(), m.indices.size() * 2);
    for (float x : m.positions) ASSERT_TRUE(std::isfinite(x));
    for (float uv : s.shape.corner_uv) {
      ASSERT_GE(uv, 0.0f);
      ASSERT_LE(uv, 1.0f);
    }
  }
}

TEST(Shapes, TopologyIsAsIntended) {
  EXPECT_EQ(euler_characteristic(make_plane(10, 7).mesh), 1);          // disc
  EXPECT_EQ(euler_characteristic(make_cylinder_open(16, 5).mesh), 0);  // annulus
  EXPECT_EQ(euler_characteristic(make_sphere(16, 8).mesh), 2);
  EXPECT_EQ(euler_characteristic(make_bumpy_sphere(16, 8).mesh), 2);
  EXPECT_EQ(euler_characteristic(make_torus(16, 8).mesh), 0);
  EXPECT_EQ(euler_characteristic(make_twisted_loop(32, 8).mesh), 0);
  EXPECT_EQ(euler_characteristic(make_twisted_cone(16, 8).mesh), 1);  // disc with apex
}

TEST(Shapes, TwistedConeIsNonUniform) {
  const TriMesh m = make_twisted_cone(24, 12).mesh;
  double lo = 1e30, hi = 0;
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const float* p = m.positions.data();
    const uint32_t* t = &m.indices[3 * f];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = p[3 * t[1] + k] - p[3 * t[0] + k];
      e2[k] = p[3 * t[2] + k] - p[3 * t[0] + k];
    }
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                 cz = e1[0] * e2[1] - e1[1] * e2[0];
    const double a = std::sqrt(cx * cx + cy * cy + cz * cz);
    lo = std::min(lo, a), hi = std::max(hi, a);
  }
  EXPECT_GT(hi / lo, 10.0);
}

TEST(Shapes, DegenerateSoupHasItsDefects) {
  const TriMesh m = make_degenerate_soup().mesh;
  const VertexFaces vf = build_vertex_faces(m);
  const std::vector<uint32_t> opp = build_opposite_corners(m, vf);
  int repeated = 0;
  for (uint32_t f = 0; f < m.face_count(); ++f) repeated += face_has_repeated_vertex(m, f);
  EXPECT_GE(repeated, 1);
  // The fin makes an edge with three faces: none of them is paired across it.
  const uint32_t fin_face = 72 + 3;  // 6x6 plane has 72 faces; the fin is the 4th extra
  bool unpaired = false;
  for (int k = 0; k < 3; ++k) unpaired |= opp[3 * fin_face + k] == kNone;
  EXPECT_TRUE(unpaired);
}

}  // namespace
}  // namespace gltfwarp
