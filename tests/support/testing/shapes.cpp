// Parametric test surfaces after the models in Sorkine & Cohen-Or 2001
// (section 4: twisted cone, twisted loop, sphere, plane, cut cylinder).
// Built over a (u, v) grid; the grid parameter is the source UV.
#include "tests/support/testing/shapes.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace gltfwarp {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct GridSpec {
  int nu = 1, nv = 1;
  bool wrap_u = false;                    // column nu welds to column 0
  bool wrap_v = false;                    // row nv welds to row 0
  bool pole_v0 = false, pole_v1 = false;  // rows 0 / nv collapse to one vertex
  bool alternate = false;                 // alternate the quad diagonal
};

// Vertices at grid nodes (welded as the spec says), two triangles per quad,
// triangles that name a vertex twice (at poles) dropped.
ShapeMesh build_grid(const GridSpec& g, const std::function<void(double, double, double*)>& fn,
                     const std::function<double(int)>& u_of = nullptr,
                     const std::function<double(int)>& v_of = nullptr) {
  auto uval = [&](int i) { return u_of ? u_of(i) : double(i) / g.nu; };
  auto vval = [&](int j) { return v_of ? v_of(j) : double(j) / g.nv; };
  const int cols = g.wrap_u ? g.nu : g.nu + 1;
  const int rows = g.wrap_v ? g.nv : g.nv + 1;
  ShapeMesh s;
  std::vector<uint32_t> id(size_t(cols) * rows);
  uint32_t pole0 = 0, pole1 = 0;
  auto push = [&](double u, double v) {
    double p[3];
    fn(u, v, p);
    for (double c : p) s.mesh.positions.push_back(float(c));
    return s.mesh.vertex_count() - 1;
  };
  if (g.pole_v0) pole0 = push(0.0, 0.0);
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      if (g.pole_v0 && j == 0) {
        id[size_t(j) * cols + i] = pole0;
        continue;
      }
      if (g.pole_v1 && j == g.nv) {
        if (i == 0) pole1 = push(0.0, 1.0);
        id[size_t(j) * cols + i] = pole1;
        continue;
      }
      id[size_t(j) * cols + i] = push(uval(i), vval(j));
    }
  }
  auto vid = [&](int i, int j) {
    const int ii = g.wrap_u ? i % g.nu : i, jj = g.wrap_v ? j % g.nv : j;
    return id[size_t(jj) * cols + ii];
  };
  for (int j = 0; j < g.nv; ++j) {
    for (int i = 0; i < g.nu; ++i) {
      const int ci[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
      const bool flip = g.alternate && ((i + j) & 1);
      const int tris[2][3] = {{0, 1, flip ? 3 : 2}, {flip ? 1 : 0, 2, 3}};
      for (const auto& t : tris) {
        uint32_t v[3];
        for (int k = 0; k < 3; ++k) v[k] = vid(ci[t[k]][0], ci[t[k]][1]);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
        for (int k = 0; k < 3; ++k) {
          s.mesh.indices.push_back(v[k]);
          s.corner_uv.push_back(float(uval(ci[t[k]][0])));
          s.corner_uv.push_back(float(vval(ci[t[k]][1])));
        }
      }
    }
  }
  return s;
}

}  // namespace

ShapeMesh make_plane(int nx, int ny) {
  GridSpec g;
  g.nu = nx;
  g.nv = ny;
  return build_grid(g, [](double u, double v, double* p) {
    p[0] = u;
    p[1] = v;
    p[2] = 0;
  });
}

ShapeMesh make_cylinder_open(int seg, int rings) {
  GridSpec g;
  g.nu = seg;
  g.nv = rings;
  g.wrap_u = true;
  return build_grid(g, [](double u, double v, double* p) {
    p[0] = std::cos(2 * kPi * u);
    p[1] = std::sin(2 * kPi * u);
    p[2] = 2.0 * v;
  });
}

static ShapeMesh sphere_like(int seg, int rings, double amp, int lobes) {
  GridSpec g;
  g.nu = seg;
  g.nv = rings;
  g.wrap_u = true;
  g.pole_v0 = g.pole_v1 = true;
  return build_grid(g, [amp, lobes](double u, double v, double* p) {
    const double th = 2 * kPi * u, ph = kPi * v;
    const double r = 1.0 + amp * std::sin(lobes * th) * std::sin(lobes * ph);
    p[0] = r * std::sin(ph) * std::cos(th);
    p[1] = r * std::sin(ph) * std::sin(th);
    p[2] = r * std::cos(ph);
  });
}

ShapeMesh make_sphere(int seg, int rings) { return sphere_like(seg, rings, 0.0, 0); }
ShapeMesh make_bumpy_sphere(int seg, int rings, double amplitude, int lobes) {
  return sphere_like(seg, rings, amplitude, lobes);
}

ShapeMesh make_torus(int seg, int rings, double major, double minor) {
  GridSpec g;
  g.nu = seg;
  g.nv = rings;
  g.wrap_u = g.wrap_v = true;
  return build_grid(g, [major, minor](double u, double v, double* p) {
    const double a = 2 * kPi * u, b = 2 * kPi * v;
    p[0] = (major + minor * std::cos(b)) * std::cos(a);
    p[1] = (major + minor * std::cos(b)) * std::sin(a);
    p[2] = minor * std::sin(b);
  });
}

ShapeMesh make_twisted_loop(int seg, int rings) {
  GridSpec g;
  g.nu = seg;
  g.nv = rings;
  g.wrap_u = g.wrap_v = true;
  g.alternate = true;
  // Elliptic section (0.45 x 0.15) turning twice around the loop: high
  // curvature, genus 1. Two full turns keep the section periodic.
  return build_grid(g, [](double u, double v, double* p) {
    const double a = 2 * kPi * u, b = 2 * kPi * v, tw = 2.0 * a;
    const double ex = 0.45 * std::cos(b), ey = 0.15 * std::sin(b);
    const double rx = ex * std::cos(tw) - ey * std::sin(tw);
    const double rz = ex * std::sin(tw) + ey * std::cos(tw);
    p[0] = (1.0 + rx) * std::cos(a);
    p[1] = (1.0 + rx) * std::sin(a);
    p[2] = rz + 0.3 * std::sin(3 * a);
  });
}

ShapeMesh make_twisted_cone(int seg, int rings) {
  GridSpec g;
  g.nu = seg;
  g.nv = rings;
  g.wrap_u = true;
  g.pole_v1 = true;
  g.alternate = true;
  // Rings graded geometrically towards the apex and columns jittered, so
  // triangle sizes vary by an order of magnitude.
  auto v_of = [rings](int j) { return 1.0 - std::pow(1.0 - double(j) / rings, 1.7); };
  auto u_of = [seg](int i) {
    const double jitter = (i % seg) == 0 ? 0.0 : 0.3 * std::sin(7.3 * i) / seg;
    return (double(i) + 0.0) / seg + jitter;
  };
  return build_grid(
      g,
      [](double u, double v, double* p) {
        const double r = 1.0 - v, a = 2 * kPi * u + 2.5 * v * v;
        p[0] = r * std::cos(a) * (1.0 + 0.4 * v);
        p[1] = r * std::sin(a);
        p[2] = 2.5 * v;
      },
      u_of, v_of);
}

ShapeMesh concat(const ShapeMesh& a, const ShapeMesh& b) {
  ShapeMesh s = a;
  const uint32_t off = a.mesh.vertex_count();
  s.mesh.positions.insert(s.mesh.positions.end(), b.mesh.positions.begin(), b.mesh.positions.end());
  for (uint32_t i : b.mesh.indices) s.mesh.indices.push_back(i + off);
  s.corner_uv.insert(s.corner_uv.end(), b.corner_uv.begin(), b.corner_uv.end());
  return s;
}

ShapeMesh make_degenerate_soup() {
  ShapeMesh s = make_plane(6, 6);
  TriMesh& m = s.mesh;
  auto add_vertex = [&](float x, float y, float z) {
    m.positions.insert(m.positions.end(), {x, y, z});
    return m.vertex_count() - 1;
  };
  auto add_face = [&](uint32_t a, uint32_t b, uint32_t c) {
    m.indices.insert(m.indices.end(), {a, b, c});
    s.corner_uv.insert(s.corner_uv.end(), {0.f, 0.f, 1.f, 0.f, 0.f, 1.f});
  };
  // Collinear (zero-area) face on existing vertices 0, 1, 2 (a row of the grid).
  add_face(0, 1, 2);
  // Repeated-vertex face.
  add_face(3, 3, 10);
  // Duplicate of face 0.
  add_face(m.indices[0], m.indices[1], m.indices[2]);
  // Non-manifold fin on the edge of face 5 (third face on that edge).
  const uint32_t fin = add_vertex(0.5f, 0.5f, 0.7f);
  add_face(m.indices[15], m.indices[16], fin);
  // Zero-length edge: a vertex coincident with vertex 7.
  const uint32_t twin = add_vertex(m.positions[21], m.positions[22], m.positions[23]);
  add_face(7, twin, 8);
  // Isolated face, far away.
  const uint32_t i0 = add_vertex(5, 5, 5), i1 = add_vertex(6, 5, 5), i2 = add_vertex(5, 6, 5);
  add_face(i0, i1, i2);
  // Isolated zero-area face with all three vertices coincident.
  const uint32_t z0 = add_vertex(9, 9, 9), z1 = add_vertex(9, 9, 9), z2 = add_vertex(9, 9, 9);
  add_face(z0, z1, z2);
  // A second component.
  ShapeMesh tube = make_cylinder_open(8, 3);
  for (size_t i = 0; i < tube.mesh.positions.size(); i += 3) tube.mesh.positions[i] += 4.0f;
  return concat(s, tube);
}

std::vector<NamedShape> standard_shapes(int target_faces) {
  auto side = [&](double k) { return std::max(3, int(std::sqrt(target_faces / k))); };
  const int n = side(2.0);
  std::vector<NamedShape> out;
  out.push_back({"plane", make_plane(n, n)});
  out.push_back({"cylinder_open", make_cylinder_open(2 * side(4.0), side(4.0))});
  out.push_back({"sphere", make_sphere(2 * side(4.0), side(4.0))});
  out.push_back({"bumpy_sphere", make_bumpy_sphere(2 * side(4.0), side(4.0))});
  out.push_back({"twisted_loop", make_twisted_loop(4 * side(8.0), side(8.0))});
  out.push_back({"twisted_cone", make_twisted_cone(2 * side(4.0), side(4.0))});
  out.push_back({"torus", make_torus(2 * side(4.0), side(4.0))});
  out.push_back({"degenerate_soup", make_degenerate_soup()});
  return out;
}

}  // namespace gltfwarp
