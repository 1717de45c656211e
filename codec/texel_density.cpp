// Texel density measure (see texel_density.h for the source).
#include "codec/texel_density.h"

#include <algorithm>
#include <cmath>

namespace gltfwarp {
namespace {

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

}  // namespace

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
  double scale = 0;
  switch (options.mode) {
    case DensityMode::preserve_texel_count:
      // The layout is near-isometric, so an atlas at scale s spends about
      // s^2 * surface_area texels on the surface: match the source's budget.
      scale = std::sqrt(r.source_texels / r.surface_area);
      break;
    case DensityMode::percentile:
      scale = pct(std::clamp(options.percentile, 0.0, 1.0));
      break;
  }
  r.texel_scale = std::max(scale, options.min_scale);
  return r;
}

}  // namespace gltfwarp
