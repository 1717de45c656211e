// Tangent frames: orthonormal, glTF handedness on planes with known UVs,
// seams keep separate frames, the per-vertex form agrees with the per-corner one.
#include <gtest/gtest.h>

#include <cmath>

#include "codec/decode/tangents.h"

namespace gltfwarp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An n x n grid on the XY plane, z = 0, with per-vertex uv = f(x, y).
struct Grid {
  TriMesh mesh;
  std::vector<float> uv_vertex, normals_vertex;
};

template <class F>
Grid make_grid(int n, F uv_of) {
  Grid g;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / n, y = float(j) / n;
      g.mesh.positions.insert(g.mesh.positions.end(), {x, y, 0.0f});
      float u, v;
      uv_of(x, y, u, v);
      g.uv_vertex.insert(g.uv_vertex.end(), {u, v});
      g.normals_vertex.insert(g.normals_vertex.end(), {0.0f, 0.0f, 1.0f});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      g.mesh.indices.insert(g.mesh.indices.end(), {a, b, c, a, c, d});  // ccw seen from +z
    }
  return g;
}

void expect_frames(const std::vector<float>& t, const std::vector<float>& normals, double tx, double ty,
                   double tz, float w) {
  for (size_t c = 0; c < t.size() / 4; ++c) {
    const double x = t[4 * c], y = t[4 * c + 1], z = t[4 * c + 2];
    EXPECT_NEAR(x * x + y * y + z * z, 1.0, 1e-5);
    EXPECT_NEAR(x * normals[3 * c] + y * normals[3 * c + 1] + z * normals[3 * c + 2], 0.0, 1e-5);
    EXPECT_NEAR(x, tx, 1e-5) << c;
    EXPECT_NEAR(y, ty, 1e-5) << c;
    EXPECT_NEAR(z, tz, 1e-5) << c;
    EXPECT_EQ(t[4 * c + 3], w) << c;
  }
}

TEST(Tangents, GltfPlaneIsRightHanded) {
  // The usual glTF quad: u = x, v = 1 - y (image top at y = 1), normal +z:
  // tangent +x, bitangent cross(N, T) = +y is image up, so w = +1.
  const Grid g = make_grid(4, [](float x, float y, float& u, float& v) { u = x, v = 1 - y; });
  const auto cn = per_corner(g.mesh, g.normals_vertex, 3), cu = per_corner(g.mesh, g.uv_vertex, 2);
  expect_frames(corner_tangents(g.mesh, cn, cu), cn, 1, 0, 0, 1.0f);
}

TEST(Tangents, MirroredUvsFlipW) {
  const Grid g = make_grid(3, [](float x, float y, float& u, float& v) { u = 1 - x, v = 1 - y; });
  const auto cn = per_corner(g.mesh, g.normals_vertex, 3), cu = per_corner(g.mesh, g.uv_vertex, 2);
  expect_frames(corner_tangents(g.mesh, cn, cu), cn, -1, 0, 0, -1.0f);
}

TEST(Tangents, RotatedUvsTurnTheTangent) {
  const double a = 0.6;
  const Grid g = make_grid(3, [&](float x, float y, float& u, float& v) {
    // uv = R(-a) (x, y) then v flipped: the u axis points along (cos a, sin a).
    u = float(std::cos(a) * x + std::sin(a) * y);
    v = float(1 - (-std::sin(a) * x + std::cos(a) * y));
  });
  const auto cn = per_corner(g.mesh, g.normals_vertex, 3), cu = per_corner(g.mesh, g.uv_vertex, 2);
  expect_frames(corner_tangents(g.mesh, cn, cu), cn, std::cos(a), std::sin(a), 0, 1.0f);
}

TEST(Tangents, CylinderFramesAreOrthonormal) {
  TriMesh m;
  std::vector<float> normals, uvs;
  const int n = 16;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= n; ++i) {  // duplicate seam column, as glTF would
      const double a = 2 * kPi * i / n;
      m.positions.insert(m.positions.end(), {float(std::cos(a)), float(std::sin(a)), float(j)});
      normals.insert(normals.end(), {float(std::cos(a)), float(std::sin(a)), 0.0f});
      uvs.insert(uvs.end(), {float(double(i) / n), float(1 - j)});
    }
  for (int i = 0; i < n; ++i) {
    const uint32_t a = i, b = i + 1, c = n + 2 + i, d = n + 1 + i;
    m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
  }
  const auto vt = vertex_tangents(m.positions, normals, uvs, m.indices);
  ASSERT_EQ(vt.size(), size_t(m.vertex_count()) * 4);
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    const double x = vt[4 * v], y = vt[4 * v + 1], z = vt[4 * v + 2];
    EXPECT_NEAR(x * x + y * y + z * z, 1, 1e-5);
    EXPECT_NEAR(x * normals[3 * v] + y * normals[3 * v + 1] + z * normals[3 * v + 2], 0, 1e-5);
    // u grows counter-clockwise: tangent is the circle's tangent (-sin, cos, 0).
    const double a = 2 * kPi * (v % (n + 1)) / n;
    EXPECT_NEAR(x, -std::sin(a), 1e-5);
    EXPECT_NEAR(y, std::cos(a), 1e-5);
    EXPECT_EQ(vt[4 * v + 3], 1.0f);  // cross(N, T) = +z, v decreases with z: image up
  }
  // Per-corner and per-vertex forms agree.
  const auto ct = corner_tangents(m, per_corner(m, normals, 3), per_corner(m, uvs, 2));
  for (size_t c = 0; c < m.indices.size(); ++c)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(ct[4 * c + k], vt[4 * m.indices[c] + k], 1e-6);
}

TEST(Tangents, SeamsKeepSeparateFrames) {
  // Two triangles share an edge; the second has mirrored UVs (a mirror seam
  // with equal UVs on the shared vertices): orientation splits the groups.
  TriMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0};
  m.indices = {0, 1, 2, 1, 3, 2};
  const std::vector<float> uv = {0, 1, 1, 1, 1, 0,   // face 0: u = x
                                 1, 1, 0, 1, 1, 0};  // face 1: u = 2 - x (mirrored)
  std::vector<float> n(18);
  for (int c = 0; c < 6; ++c) n[3 * c + 2] = 1;
  const auto t = corner_tangents(m, n, uv);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(t[4 * c], 1, 1e-6);
    EXPECT_EQ(t[4 * c + 3], 1.0f);
  }
  for (int c = 3; c < 6; ++c) {
    EXPECT_NEAR(t[4 * c], -1, 1e-6);
    EXPECT_EQ(t[4 * c + 3], -1.0f);
  }
}

TEST(Tangents, DegenerateUvsGiveAValidFrame) {
  TriMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  m.indices = {0, 1, 2};
  const std::vector<float> uv(6, 0.5f);
  const auto n = flat_corner_normals(m);
  EXPECT_NEAR(n[2], 1, 1e-6);
  const auto t = corner_tangents(m, n, uv);
  for (int c = 0; c < 3; ++c) {
    const double x = t[4 * c], y = t[4 * c + 1], z = t[4 * c + 2];
    EXPECT_NEAR(x * x + y * y + z * z, 1, 1e-6);
    EXPECT_NEAR(z, 0, 1e-6);
  }
}

}  // namespace
}  // namespace gltfwarp
