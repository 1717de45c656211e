// Generated test models like the paper's (plane, open cylinder, sphere,
// twisted cone with non-uniform triangles, twisted loop of genus 1), plus
// degenerate and non-manifold variants for robustness tests. Each carries a
// natural source UV per corner (its parameter domain), as a glTF would.
#pragma once

#include <string>
#include <vector>

#include "codec/core/mesh.h"

namespace gltfwarp {

struct ShapeMesh {
  TriMesh mesh;
  std::vector<float> corner_uv;  // 2 per corner, in [0, 1]
};

ShapeMesh make_plane(int nx, int ny);              // unit square, regular grid
ShapeMesh make_cylinder_open(int seg, int rings);  // tube without caps, welded around
ShapeMesh make_sphere(int seg, int rings);         // UV sphere, single pole vertices
ShapeMesh make_bumpy_sphere(int seg, int rings, double amplitude = 0.15, int lobes = 5);
ShapeMesh make_torus(int seg, int rings, double major = 1.0, double minor = 0.35);
ShapeMesh make_twisted_loop(int seg, int rings);  // torus with a twisted elliptic section
ShapeMesh make_twisted_cone(int seg, int rings);  // graded rings, jittered: non-uniform
// A plane plus zero-area faces (collinear and repeated-vertex), a duplicate
// face, an isolated face, a fin making a non-manifold edge shared by three
// faces, zero-length edges, and a second component.
ShapeMesh make_degenerate_soup();

// Several components in one mesh (indices offset).
ShapeMesh concat(const ShapeMesh& a, const ShapeMesh& b);

struct NamedShape {
  std::string name;
  ShapeMesh shape;
};
// The standard set used by tests, at roughly `target_faces` faces each.
std::vector<NamedShape> standard_shapes(int target_faces = 2000);

}  // namespace gltfwarp
