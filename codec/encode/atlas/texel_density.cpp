// Texel density measure (see texel_density.h for the source).
#include "codec/encode/atlas/texel_density.h"

#include <algorithm>
#include <cmath>

namespace gltfwarp {
namespace {

// Distinct texels of a w x h image whose centres the UV triangles cover,
// with coordinates wrapped into the image (REPEAT). Large images are
// counted on a coarser grid (at most 4096 x 4096 cells), scaled back.
double used_texel_count(std::span<const DensityPrimitive* const> prims, uint32_t w, uint32_t h) {
  if (w == 0 || h == 0) return 0;
  uint32_t f = 1;
  while (w / f > 4096 || h / f > 4096) f *= 2;
  const uint32_t gw = (w + f - 1) / f, gh = (h + f - 1) / f;
  std::vector<uint8_t> used(size_t(gw) * gh, 0);
  uint64_t count = 0;
  for (const DensityPrimitive* p : prims) {
    const uint32_t nf = p->mesh->face_count();
    for (uint32_t t = 0; t < nf; ++t) {
      double x[3], y[3];
      for (int k = 0; k < 3; ++k) {
        x[k] = double(p->source_uv[6 * size_t(t) + 2 * k]) * gw;
        y[k] = double(p->source_uv[6 * size_t(t) + 2 * k + 1]) * gh;
      }
      double area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
      if (!(std::abs(area) > 0) || !std::isfinite(area)) continue;
      if (area < 0) std::swap(x[1], x[2]), std::swap(y[1], y[2]);
      const double x0 = std::min({x[0], x[1], x[2]}), x1 = std::max({x[0], x[1], x[2]});
      const double y0 = std::min({y[0], y[1], y[2]}), y1 = std::max({y[0], y[1], y[2]});
      if (x1 - x0 > 16.0 * gw || y1 - y0 > 16.0 * gh) continue;  // absurd spans: skip
      for (long long j = (long long)std::ceil(y0 - 0.5); j <= (long long)std::floor(y1 - 0.5); ++j)
        for (long long i = (long long)std::ceil(x0 - 0.5); i <= (long long)std::floor(x1 - 0.5); ++i) {
          const double cx = double(i) + 0.5, cy = double(j) + 0.5;
          bool in = true;
          for (int e = 0; e < 3 && in; ++e) {
            const int n = (e + 1) % 3;
            in = (x[n] - x[e]) * (cy - y[e]) - (y[n] - y[e]) * (cx - x[e]) >= 0;
          }
          if (!in) continue;
          const long long wi = ((i % gw) + gw) % gw, wj = ((j % gh) + gh) % gh;
          uint8_t& u = used[size_t(wj) * gw + size_t(wi)];
          if (!u) u = 1, ++count;
        }
    }
  }
  return double(count) * f * f;
}

}  // namespace

double face_area3d(const TriMesh& m, uint32_t f) {
  const float* p0 = &m.positions[3 * m.indices[3 * f + 0]];
  const float* p1 = &m.positions[3 * m.indices[3 * f + 1]];
  const float* p2 = &m.positions[3 * m.indices[3 * f + 2]];
  double e1[3], e2[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = double(p1[i]) - p0[i];
    e2[i] = double(p2[i]) - p0[i];
  }
  const double cx = e1[1] * e2[2] - e1[2] * e2[1];
  const double cy = e1[2] * e2[0] - e1[0] * e2[2];
  const double cz = e1[0] * e2[1] - e1[1] * e2[0];
  return 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
}

double face_area_texels(std::span<const float> uv, uint32_t f, double w, double h) {
  const float* a = &uv[6 * f];
  const double ux = (double(a[2]) - a[0]) * w, uy = (double(a[3]) - a[1]) * h;
  const double vx = (double(a[4]) - a[0]) * w, vy = (double(a[5]) - a[1]) * h;
  return 0.5 * std::abs(ux * vy - uy * vx);
}

std::vector<double> triangle_texel_density(const TriMesh& mesh, std::span<const float> source_uv,
                                           uint32_t image_width, uint32_t image_height) {
  const uint32_t nf = mesh.face_count();
  std::vector<double> d(nf, 0.0);
  if (source_uv.size() < size_t(6) * nf) return d;
  for (uint32_t f = 0; f < nf; ++f) {
    const double a3 = face_area3d(mesh, f);
    if (!(a3 > 0)) continue;
    d[f] = std::sqrt(face_area_texels(source_uv, f, image_width, image_height) / a3);
  }
  return d;
}

std::vector<PatchDensity> patch_densities(std::span<const double> corner_xy,
                                          std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                                          std::span<const double> face_density, double quantile) {
  std::vector<PatchDensity> out(patch_count);
  std::vector<std::vector<std::pair<double, double>>> faces(patch_count);  // (density, area)
  for (size_t f = 0; f < patch_of_face.size(); ++f) {
    const double a = layout_face_area(corner_xy, f);
    const double d = face_density[f];
    if (!(a > 0) || !std::isfinite(d) || !(d > 0)) continue;
    PatchDensity& p = out[patch_of_face[f]];
    p.area += a, p.squared += a * d * d;
    faces[patch_of_face[f]].push_back({d, a});
  }
  for (uint32_t pi = 0; pi < patch_count; ++pi) {
    PatchDensity& p = out[pi];
    auto& dens = faces[pi];
    if (!(p.area > 0)) continue;
    if (quantile > 0) {
      std::sort(dens.begin(), dens.end());
      const double target = std::min(quantile, 1.0) * p.area;
      double acc = 0;
      p.density = dens.back().first;
      for (const auto& [d, a] : dens)
        if ((acc += a) >= target) {
          p.density = d;
          break;
        }
    } else {
      p.density = std::sqrt(p.squared / p.area);
    }
  }
  return out;
}

bool layout_to_source_jacobian(std::span<const double> corner_xy, std::span<const float> source_uv, size_t f,
                               double width, double height, double j[4]) {
  const double* c = &corner_xy[6 * f];
  const float* u = &source_uv[6 * f];
  const double e1x = c[2] - c[0], e1y = c[3] - c[1], e2x = c[4] - c[0], e2y = c[5] - c[1];
  const double det = e1x * e2y - e2x * e1y;
  if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
  const double t1x = (double(u[2]) - u[0]) * width, t1y = (double(u[3]) - u[1]) * height;
  const double t2x = (double(u[4]) - u[0]) * width, t2y = (double(u[5]) - u[1]) * height;
  // J = [t1 t2] * inverse([e1 e2]).
  j[0] = (t1x * e2y - t2x * e1y) / det, j[1] = (t2x * e1x - t1x * e2x) / det;
  j[2] = (t1y * e2y - t2y * e1y) / det, j[3] = (t2y * e1x - t1y * e2x) / det;
  return true;
}

std::vector<double> layout_texel_density(std::span<const double> corner_xy, std::span<const float> source_uv,
                                         uint32_t image_width, uint32_t image_height) {
  const size_t nf = std::min(corner_xy.size(), source_uv.size()) / 6;
  std::vector<double> out(nf, 0.0);
  for (size_t f = 0; f < nf; ++f) {
    double j[4];
    if (!layout_to_source_jacobian(corner_xy, source_uv, f, image_width, image_height, j)) continue;
    const double a = j[0], b = j[1], cc = j[2], d = j[3];
    // Singular values of [[a b] [cc d]]: the largest, and their product |det|.
    const double s1 = a * a + b * b + cc * cc + d * d, s2 = a * d - b * cc;
    const double sigma = std::sqrt(0.5 * (s1 + std::sqrt(std::max(0.0, s1 * s1 - 4 * s2 * s2))));
    // Geometric mean of the largest stretch and the area-preserving one.
    const double v = std::sqrt(sigma * std::sqrt(std::abs(s2)));
    if (std::isfinite(v)) out[f] = v;
  }
  return out;
}

TexelDensityReport auto_texel_scale(std::span<const DensityPrimitive> prims,
                                    const TexelDensityOptions& options) {
  TexelDensityReport r;
  struct Sample {
    double density, area;
  };
  std::vector<Sample> samples;
  double weighted = 0;
  for (const DensityPrimitive& p : prims) {
    if (!p.mesh) continue;
    const uint32_t nf = p.mesh->face_count();
    if (p.source_uv.size() < size_t(6) * nf) continue;
    for (uint32_t f = 0; f < nf; ++f) {
      const double a3 = face_area3d(*p.mesh, f);
      if (!(a3 > 0)) continue;
      const double at = face_area_texels(p.source_uv, f, p.image_width, p.image_height);
      if (!(at > 0)) ++r.degenerate_uv;
      const double dens = std::sqrt(at / a3);
      samples.push_back({dens, a3});
      r.source_texels += at;
      r.surface_area += a3;
      weighted += dens * a3;
      r.max_density = std::max(r.max_density, dens);
      ++r.triangles;
    }
  }
  if (samples.empty() || !(r.surface_area > 0)) {
    r.texel_scale = options.min_scale;
    return r;
  }
  r.mean_density = weighted / r.surface_area;
  std::sort(samples.begin(), samples.end(),
            [](const Sample& a, const Sample& b) { return a.density < b.density; });
  auto pct = [&](double q) {
    const double target = q * r.surface_area;
    double acc = 0;
    for (const Sample& s : samples) {
      acc += s.area;
      if (acc >= target) return s.density;
    }
    return samples.back().density;
  };
  r.p50_density = pct(0.5);
  r.p90_density = pct(0.9);
  // Distinct texels used, per image size.
  {
    std::vector<std::pair<uint64_t, const DensityPrimitive*>> by_size;
    for (const DensityPrimitive& p : prims)
      if (p.mesh && p.source_uv.size() >= size_t(6) * p.mesh->face_count())
        by_size.push_back({uint64_t(p.image_width) << 32 | p.image_height, &p});
    std::sort(by_size.begin(), by_size.end());
    for (size_t i = 0; i < by_size.size();) {
      size_t j = i;
      std::vector<const DensityPrimitive*> group;
      while (j < by_size.size() && by_size[j].first == by_size[i].first) group.push_back(by_size[j++].second);
      r.used_texels += used_texel_count(group, group[0]->image_width, group[0]->image_height);
      i = j;
    }
  }
  double scale = 0;
  switch (options.mode) {
    case DensityMode::preserve_used_texels:
      scale = std::sqrt(r.used_texels / r.surface_area);
      break;
    case DensityMode::preserve_texel_count:
      // The layout is near-isometric, so an atlas at scale s spends about
      // s^2 * surface_area texels on the surface: match the source's budget.
      scale = std::sqrt(r.source_texels / r.surface_area);
      break;
    case DensityMode::percentile:
      scale = pct(std::clamp(options.percentile, 0.0, 1.0));
      break;
  }
  // Floor at one texel over the whole surface, relative to the model's own
  // units: an absolute floor in texels per unit blew a model measured in
  // units of 1e30 up to the atlas cap (a 5x5 grid warped 14M texels).
  r.texel_scale = std::max(scale, 1 / std::sqrt(r.surface_area));
  return r;
}

}  // namespace gltfwarp
