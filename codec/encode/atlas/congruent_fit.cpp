// Least-squares similarity fit and the copy's fine placement (congruent_fit.h).
#include "codec/encode/atlas/congruent_fit.h"

#include <algorithm>
#include <cmath>

namespace gltfwarp {
namespace {

SimilarityFit fit_one(std::span<const double> from, std::span<const double> to, bool mirror) {
  SimilarityFit f;
  f.mirror = mirror;
  const size_t n = std::min(from.size(), to.size()) / 2;
  if (n < 2) return f;
  const double m = mirror ? -1.0 : 1.0;
  double fx = 0, fy = 0, gx = 0, gy = 0;
  for (size_t i = 0; i < n; ++i)
    fx += from[2 * i], fy += m * from[2 * i + 1], gx += to[2 * i], gy += to[2 * i + 1];
  fx /= double(n), fy /= double(n), gx /= double(n), gy /= double(n);
  // Centred: a = sum(p.q) / sum(p.p), b = sum(p x q) / sum(p.p).
  double pp = 0, dot = 0, cross = 0;
  for (size_t i = 0; i < n; ++i) {
    const double px = from[2 * i] - fx, py = m * from[2 * i + 1] - fy;
    const double qx = to[2 * i] - gx, qy = to[2 * i + 1] - gy;
    pp += px * px + py * py;
    dot += px * qx + py * qy;
    cross += px * qy - py * qx;
  }
  if (!(pp > 0)) return f;
  f.a = dot / pp, f.b = cross / pp;
  f.tx = gx - (f.a * fx - f.b * fy);
  f.ty = gy - (f.b * fx + f.a * fy);
  for (size_t i = 0; i < n; ++i) {
    const double px = from[2 * i], py = m * from[2 * i + 1];
    const double ex = f.a * px - f.b * py + f.tx - to[2 * i], ey = f.b * px + f.a * py + f.ty - to[2 * i + 1];
    f.max_residual = std::max(f.max_residual, std::hypot(ex, ey));
  }
  f.ok = std::isfinite(f.max_residual);
  return f;
}

}  // namespace

SimilarityFit fit_similarity(std::span<const double> from_xy, std::span<const double> to_xy) {
  const SimilarityFit same = fit_one(from_xy, to_xy, false), mirrored = fit_one(from_xy, to_xy, true);
  if (!same.ok) return mirrored;
  if (!mirrored.ok) return same;
  return mirrored.max_residual < same.max_residual ? mirrored : same;
}

PatchPlacement copy_placement(const PatchPlacement& original, const SimilarityFit& fit, double texel_scale,
                              uint32_t width, uint32_t height) {
  // Original: texel = s R p + X. Copy: texel = s R (S M q + t) + X, so its
  // rotation part is R S and its translation s R t + X (same s: same step).
  double c = 1, s = 0;
  rotation_cos_sin(original.rotation, c, s);
  const double scale = texel_scale * patch_scale(original.scale_step);
  const double cf = c * fit.a - s * fit.b, sf = s * fit.a + c * fit.b;
  const double x0 = double(original.x) + scale * (c * fit.tx - s * fit.ty);
  const double y0 = double(original.y) + scale * (s * fit.tx + c * fit.ty);
  PatchPlacement out;
  out.page = original.page;
  out.scale_step = original.scale_step;
  out.fine = true;
  out.mirror = fit.mirror;
  const int32_t lim = 2 * kFineUnit;
  out.cos_q = std::clamp(int32_t(std::lround(cf * kFineUnit)), -lim, lim);
  out.sin_q = std::clamp(int32_t(std::lround(sf * kFineUnit)), -lim, lim);
  if (out.cos_q == 0 && out.sin_q == 0) out.cos_q = 1;
  auto split = [](double v, uint32_t limit, int32_t& whole, uint32_t& frac) {
    v = std::clamp(v, 0.0, double(limit));
    long long w = (long long)std::floor(v);
    long long q = std::lround((v - double(w)) * kFineFracSteps);
    if (q >= (long long)kFineFracSteps) ++w, q = 0;
    if (w >= (long long)limit) w = limit, q = 0;
    whole = int32_t(w), frac = uint32_t(q);
  };
  split(x0, width, out.x, out.x_frac);
  split(y0, height, out.y, out.y_frac);
  return out;
}

}  // namespace gltfwarp
