// Measures of a laid-out partition: distortion, flips, seams, fill, holes.
// The paper's distortion measure is Sorkine & Cohen-Or 2001, section 3.
#include "codec/core/layout_report.h"

#include <algorithm>
#include <cmath>

#include "codec/core/distortion.h"
#include "codec/core/layout.h"
#include "codec/core/topology.h"

namespace gltfwarp {

double length3(const TriMesh& m, uint32_t u, uint32_t w) { return std::sqrt(length3_sq(m, u, w)); }

double face_area3(const TriMesh& m, uint32_t f) {
  return triangle_area3(m.positions.data(), &m.indices[3 * f]);
}

namespace {
bool face_shrunk(const TriMesh& m, uint32_t f, const Vec2 P[3], double tau) {
  return 0.5 * std::fabs(orient2d(P[0], P[1], P[2])) * tau * tau < face_area3(m, f);
}
}  // namespace

// Distortion of face f with its corners at P (paper's measure).
double face_distortion(const TriMesh& m, uint32_t f, const Vec2 P[3]) {
  const uint32_t* t = &m.indices[3 * f];
  double l3[3], l2[3];
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    l3[k] = length3(m, t[a], t[b]);
    const double dx = P[a].x - P[b].x, dy = P[a].y - P[b].y;
    l2[k] = std::sqrt(dx * dx + dy * dy);
  }
  return triangle_distortion(l3, l2);
}

bool face_within_tau(const TriMesh& m, uint32_t f, const Vec2 P[3], double tau) {
  return face_distortion(m, f, P) <= tau && !face_shrunk(m, f, P, tau);
}

// Area of the patch's triangles over the area of the min-area rectangle of
// its corners (1 for an empty or zero-area patch).
double patch_fill(std::span<const uint32_t> faces, const std::vector<double>& xy, std::vector<Vec2>& scratch,
                  double* area_out) {
  scratch.clear();
  double area = 0;
  for (uint32_t f : faces) {
    const double* c = &xy[6 * size_t{f}];
    const Vec2 P[3] = {{c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]}};
    area += std::fabs(orient2d(P[0], P[1], P[2])) * 0.5;
    scratch.insert(scratch.end(), P, P + 3);
  }
  if (area_out) *area_out = area;
  const OrientedRect r = min_area_rect(convex_hull(scratch));
  return r.area > 0 ? std::min(1.0, area / r.area) : 1.0;
}

uint32_t seam_edges_between(std::span<const uint32_t> opp, std::span<const uint32_t> label_of_face) {
  if (opp.size() != 3 * label_of_face.size()) return 0;
  uint32_t seams = 0;
  for (size_t c = 0; c < opp.size(); ++c)
    seams += opp[c] != kNone && opp[c] > c && label_of_face[c / 3] != label_of_face[opp[c] / 3];
  return seams;
}

double area_beyond_tau_at_own_scale(const TriMesh& mesh, std::span<const uint32_t> label_of_face,
                                    std::span<const double> corner_xy, double tau) {
  const uint32_t nf = mesh.face_count();
  if (label_of_face.size() != nf || corner_xy.size() != 6 * size_t{nf} || nf == 0) return 0;
  const uint32_t labels = *std::max_element(label_of_face.begin(), label_of_face.end()) + 1;
  auto corners = [&](uint32_t f, double s, Vec2 P[3]) {
    for (int k = 0; k < 3; ++k)
      P[k] = {s * corner_xy[6 * size_t{f} + 2 * k], s * corner_xy[6 * size_t{f} + 2 * k + 1]};
  };
  std::vector<double> log_sum(labels, 0.0), weight(labels, 0.0), area(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    Vec2 P[3];
    corners(f, 1.0, P);
    const uint32_t* t = &mesh.indices[3 * size_t{f}];
    double log_ratio = 0;
    bool finite = true;
    for (int k = 0; k < 3 && finite; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const double l3 = length3(mesh, t[a], t[b]), l2 = std::hypot(P[a].x - P[b].x, P[a].y - P[b].y);
      finite = l3 > 0 && l2 > 0 && std::isfinite(l3) && std::isfinite(l2);
      if (finite) log_ratio += std::log(l2 / l3) / 3;
    }
    area[f] = face_area3(mesh, f);
    if (finite && area[f] > 0)
      log_sum[label_of_face[f]] += area[f] * log_ratio, weight[label_of_face[f]] += area[f];
  }
  double beyond = 0, total = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t l = label_of_face[f];
    Vec2 P[3];
    corners(f, weight[l] > 0 ? std::exp(-log_sum[l] / weight[l]) : 1.0, P);
    total += area[f];
    if (!face_within_tau(mesh, f, P, tau)) beyond += area[f];
  }
  return total > 0 ? beyond / total : 0.0;
}

uint32_t hole_host(std::span<const uint32_t> opposite_corner, std::span<const uint32_t> patch_of_face,
                   std::span<const uint32_t> faces, uint32_t p) {
  if (faces.empty() || faces.size() > 3) return kNone;
  uint32_t host = kNone;
  for (uint32_t f : faces)
    for (int k = 0; k < 3; ++k) {
      const uint32_t o = opposite_corner[3 * size_t{f} + k];
      if (o == kNone) return kNone;
      const uint32_t q = patch_of_face[o / 3];
      if (q == p) continue;
      if (host != kNone && host != q) return kNone;
      host = q;
    }
  return host;
}

EmbedReport measure_embedding(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                              uint32_t patch_count, std::span<const double> corner_xy, double tau) {
  EmbedReport r;
  const uint32_t nf = mesh.face_count();
  if (!mesh_indices_valid(mesh) || patch_of_face.size() != nf || corner_xy.size() != size_t{nf} * 6) return r;
  for (uint32_t f = 0; f < nf; ++f)
    if (patch_of_face[f] >= patch_count) return r;
  r.patch_count = patch_count;
  r.face_count = nf;
  double sum = 0, wsum = 0, wtot = 0;
  uint32_t finite = 0;
  r.max_distortion = nf ? 0.0 : 1.0;
  for (uint32_t f = 0; f < nf; ++f) {
    const double* c = &corner_xy[6 * size_t{f}];
    const Vec2 P[3] = {{c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]}};
    const int s = orient2d_sign(P[0], P[1], P[2]);
    r.flipped += s < 0;
    r.zero_area += s == 0;
    const double d = face_distortion(mesh, f, P);
    r.max_distortion = std::max(r.max_distortion, d);
    r.over_tau += !(d <= tau);
    r.shrunk += face_shrunk(mesh, f, P, tau);
    if (std::isfinite(d)) {
      const double a = face_area3(mesh, f);
      sum += d, ++finite;
      wsum += a * d, wtot += a;
    }
  }
  r.mean_distortion = finite ? sum / finite : 1.0;
  r.area_mean_distortion = wtot > 0 ? wsum / wtot : r.mean_distortion;

  const VertexFaces vf = build_vertex_faces(mesh);
  const std::vector<uint32_t> opp = build_opposite_corners(mesh, vf);
  for (size_t c = 0; c < opp.size(); ++c) {
    const uint32_t o = opp[c];
    if (o == kNone || o < c) continue;
    ++r.interior_edges;
    if (patch_of_face[c / 3] != patch_of_face[o / 3]) {
      ++r.seam_edges;
      const uint32_t f = uint32_t(c / 3), k = uint32_t(c % 3);
      r.seam_length += length3(mesh, mesh.indices[3 * f + (k + 1) % 3], mesh.indices[3 * f + (k + 2) % 3]);
    }
  }
  // Per patch: fill, and holes: 1-3 faces whose every edge borders one
  // other patch, the host, when the host also borders the mesh border or a
  // third patch. Without that, host and hole make a closed part on their own
  // (a cube cut 9 + 3): the host is then a disc whose outline goes round the
  // hole, and its layout encloses nothing.
  std::vector<uint32_t> first_neighbour(patch_count, kNone);
  std::vector<uint8_t> outer_border(patch_count, 0);
  for (size_t c = 0; c < opp.size(); ++c) {
    const uint32_t p = patch_of_face[c / 3];
    const uint32_t q = opp[c] == kNone ? kNone : patch_of_face[opp[c] / 3];
    if (q == p) continue;
    if (q == kNone || (first_neighbour[p] != kNone && first_neighbour[p] != q))
      outer_border[p] = 1;
    else
      first_neighbour[p] = q;
  }
  std::vector<uint32_t> off, pf;
  faces_by_patch(patch_of_face, patch_count, off, pf);
  const std::vector<double> xy(corner_xy.begin(), corner_xy.end());
  std::vector<Vec2> scratch;
  double fsum = 0, fw = 0;
  for (uint32_t p = 0; p < patch_count; ++p) {
    const std::span<const uint32_t> faces(pf.data() + off[p], off[p + 1] - off[p]);
    double area = 0;
    const double fl = patch_fill(faces, xy, scratch, &area);
    fsum += area * fl, fw += area;
    const uint32_t host = hole_host(opp, patch_of_face, faces, p);
    r.holes += host != kNone && outer_border[host];
  }
  r.fill = fw > 0 ? fsum / fw : 1.0;
  return r;
}

}  // namespace gltfwarp
