// Measures of a laid-out partition, whoever made it: the encoder's growth,
// the decoder's replay or `gltf-warp info` on a decoded file. Pure functions
// over the mesh, the patch of every face and the corners' 2D positions.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/geometry2d.h"
#include "codec/core/mesh.h"

namespace gltfwarp {

// Quality of an embedding. All figures are over the faces of one mesh.
struct EmbedReport {
  uint32_t patch_count = 0;
  uint32_t face_count = 0;
  double max_distortion = 1.0;        // over faces (degenerate faces included; see distortion.h)
  double mean_distortion = 1.0;       // unweighted over faces with a finite distortion
  double area_mean_distortion = 1.0;  // weighted by 3D face area
  uint32_t over_tau = 0;              // faces above tau (given to measure_embedding)
  uint32_t shrunk = 0;                // faces keeping less than 1/tau^2 of their 3D area (face_within_tau)
  uint32_t flipped = 0;               // 2D signed area < 0 (exact)
  uint32_t zero_area = 0;             // 2D signed area == 0 (exact)
  uint32_t seam_edges = 0;            // manifold interior edges whose two faces lie in different patches
  double seam_length = 0;             // their 3D length
  uint32_t interior_edges = 0;        // all manifold interior edges
  double fill = 0;                    // area-weighted mean of patch 2D area / its min-area-rect area
  uint32_t holes = 0;                 // patches of 1-3 faces whose every edge borders one other patch,
                                      // which also has an outer border (layout_report.cpp)
};

// Pure: measures any partition with its replayed corner positions.
EmbedReport measure_embedding(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                              uint32_t patch_count, std::span<const double> corner_xy, double tau = 1.3);

// Manifold interior edges whose two faces carry different labels: the seams
// of any face labelling (patches, source UV charts), counted as
// measure_embedding counts a partition's. opposite_corner: the mesh's
// (topology.h), built once by a caller that counts several labellings.
uint32_t seam_edges_between(std::span<const uint32_t> opposite_corner,
                            std::span<const uint32_t> label_of_face);

// The share of the surface's 3D area on faces that a layout takes past the
// encoder's rule (face_within_tau) once each label's faces are scaled by
// one factor of their own (the exp of the area-weighted mean log of 2D over
// 3D edge length): how far a source's UV charts (2D: texels) are from
// layouts the partition may make, whatever density the charts have.
double area_beyond_tau_at_own_scale(const TriMesh& mesh, std::span<const uint32_t> label_of_face,
                                    std::span<const double> corner_xy, double tau);

// The patch enclosing patch p (its faces `faces`) when they are a hole: 1 to
// 3 faces whose every edge borders one other patch, none the mesh border;
// else kNone. patch_of_face may hold kNone for faces not yet in a patch (the
// encoder's growth), which then counts as one more patch.
uint32_t hole_host(std::span<const uint32_t> opposite_corner, std::span<const uint32_t> patch_of_face,
                   std::span<const uint32_t> faces, uint32_t p);

// 3D length of the edge u-w, and 3D area of face f (double).
double length3(const TriMesh& m, uint32_t u, uint32_t w);
double face_area3(const TriMesh& m, uint32_t f);

// Distortion of face f with its corners at P (the paper's measure,
// distortion.h).
double face_distortion(const TriMesh& m, uint32_t f, const Vec2 P[3]);

// What the encoder asks of every face it lays out: the paper's distortion
// <= tau, and at least 1/tau^2 of its 3D area kept in 2D. The edge rule
// alone lets a triangle that closes a loop collapse into a needle: on the
// CesiumMilkTruck's grille a triangle with legs of 33 and 207 units was laid
// out with edges 33, 205 and 238 (every one within 1.15 of its length) and a
// ninth of its area, so the atlas gave it a ninth of its texels and the
// viewer showed streaks across the bar. A face that grows is no loss (its
// texels are more than it needs), and a degenerate 3D face keeps nothing
// to lose, so only shrinking counts. Orientation is not checked here.
bool face_within_tau(const TriMesh& m, uint32_t f, const Vec2 P[3], double tau);

// Area of the patch's triangles over the area of the min-area rectangle of
// its corners (1 for an empty or zero-area patch); the triangles' 2D area
// goes to *area_out when given. `scratch` is reused storage.
double patch_fill(std::span<const uint32_t> faces, const std::vector<double>& xy, std::vector<Vec2>& scratch,
                  double* area_out = nullptr);

}  // namespace gltfwarp
