// Least-squares atlas texels (see texel_fit.h).
#include "codec/encode/texture/texel_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gltfwarp {

double TexelFitReport::gain_db() const {
  if (!(error_before > 0) || !(error_after > 0)) return 0;
  return 10.0 * std::log10(error_before / error_after);
}

namespace {

// The bilinear stencil of one sample: four (texel, weight) pairs, texel
// indices clamped to the image as CLAMP_TO_EDGE does.
struct Stencil {
  int32_t x[2], y[2];
  float wx[2], wy[2];
};

Stencil stencil_at(float px, float py, int w, int h) {
  const double fx = double(px) - 0.5, fy = double(py) - 0.5;
  const double ix = std::floor(fx), iy = std::floor(fy);
  Stencil s;
  s.wx[1] = float(fx - ix), s.wx[0] = 1 - s.wx[1];
  s.wy[1] = float(fy - iy), s.wy[0] = 1 - s.wy[1];
  for (int k = 0; k < 2; ++k) {
    s.x[k] = int32_t(std::clamp<double>(ix + k, 0, w - 1));
    s.y[k] = int32_t(std::clamp<double>(iy + k, 0, h - 1));
  }
  return s;
}

// Offsets of the 3x3 stencil, in the order the matrix stores them.
constexpr int kDx[9] = {-1, 0, 1, -1, 0, 1, -1, 0, 1};
constexpr int kDy[9] = {-1, -1, -1, 0, 0, 0, 1, 1, 1};
constexpr int kCentre = 4;
int slot_of(int dx, int dy) { return (dy + 1) * 3 + (dx + 1); }

// Weighted squared error of the reconstruction of `texels` at the samples.
double sample_error(int w, int h, int nch, std::span<const float> xy, std::span<const float> weight,
                    std::span<const float> target, std::span<const float> texels) {
  double e = 0;
  for (size_t s = 0; s < weight.size(); ++s) {
    if (!(weight[s] > 0)) continue;
    const Stencil st = stencil_at(xy[2 * s], xy[2 * s + 1], w, h);
    for (int c = 0; c < nch; ++c) {
      double v = 0;
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i)
          v += double(st.wx[i]) * st.wy[j] * texels[(size_t(st.y[j]) * w + st.x[i]) * nch + c];
      const double d = v - target[s * nch + c];
      e += weight[s] * d * d;
    }
  }
  return e;
}

}  // namespace

TexelFitStatus fit_texels(uint32_t width, uint32_t height, int nch, std::span<const float> xy,
                          std::span<const float> weight, std::span<const float> target,
                          std::span<float> texels, const TexelFitOptions& options, TexelFitReport* report_out,
                          std::span<uint8_t> unknown) {
  TexelFitReport report;
  const int W = int(width), H = int(height);
  const size_t n_samples = weight.size();
  if (W <= 0 || H <= 0 || nch < 1 || nch > 4 || xy.size() != 2 * n_samples ||
      target.size() != n_samples * size_t(nch) || texels.size() != size_t(W) * H * nch)
    return TexelFitStatus::bad_input;

  // 1. The unknowns: texels some sample's stencil reaches with a weight.
  std::vector<int32_t> index(size_t(W) * H, -1);
  std::vector<int32_t> texel_of;  // unknown -> texel
  for (size_t s = 0; s < n_samples; ++s) {
    if (!(weight[s] > 0) || !std::isfinite(xy[2 * s]) || !std::isfinite(xy[2 * s + 1])) continue;
    ++report.samples;
    const Stencil st = stencil_at(xy[2 * s], xy[2 * s + 1], W, H);
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        if (!(st.wx[i] * st.wy[j] > 0)) continue;
        int32_t& id = index[size_t(st.y[j]) * W + st.x[i]];
        if (id < 0) id = int32_t(texel_of.size()), texel_of.push_back(int32_t(size_t(st.y[j]) * W + st.x[i]));
      }
  }
  const size_t n = texel_of.size();
  report.fitted_texels = n;
  if (!unknown.empty())
    for (int32_t t : texel_of) unknown[size_t(t)] = 1;
  if (n == 0) {
    if (report_out) *report_out = report;
    return TexelFitStatus::ok;
  }
  report.error_before = sample_error(W, H, nch, xy, weight, target, texels);

  // 2. Normal equations: A (3x3 stencil per unknown) and b.
  std::vector<double> A(n * 9, 0.0), b(n * nch, 0.0);
  for (size_t s = 0; s < n_samples; ++s) {
    if (!(weight[s] > 0) || !std::isfinite(xy[2 * s]) || !std::isfinite(xy[2 * s + 1])) continue;
    const Stencil st = stencil_at(xy[2 * s], xy[2 * s + 1], W, H);
    int32_t id[4], tx[4], ty[4];
    double bw[4];
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int k = 2 * j + i;
        tx[k] = st.x[i], ty[k] = st.y[j];
        bw[k] = double(st.wx[i]) * st.wy[j];
        id[k] = index[size_t(ty[k]) * W + tx[k]];
      }
    const double w = weight[s];
    for (int p = 0; p < 4; ++p) {
      if (!(bw[p] > 0)) continue;
      for (int c = 0; c < nch; ++c) b[size_t(id[p]) * nch + c] += w * bw[p] * target[s * nch + c];
      for (int q = 0; q < 4; ++q)
        if (bw[q] > 0) A[size_t(id[p]) * 9 + slot_of(tx[q] - tx[p], ty[q] - ty[p])] += w * bw[p] * bw[q];
    }
  }
  double mean_diag = 0;
  for (size_t u = 0; u < n; ++u) mean_diag += A[u * 9 + kCentre];
  mean_diag /= double(n);
  const double lambda = options.regularizer * mean_diag;
  std::vector<double> x(n * nch);
  for (size_t u = 0; u < n; ++u) {
    A[u * 9 + kCentre] += lambda;
    for (int c = 0; c < nch; ++c) {
      x[u * nch + c] = texels[size_t(texel_of[u]) * nch + c];
      b[u * nch + c] += lambda * x[u * nch + c];
    }
  }
  // Neighbour unknowns of each unknown (-1: not an unknown, its entry is 0).
  std::vector<int32_t> nb(n * 9, -1);
  for (size_t u = 0; u < n; ++u) {
    const int tx = texel_of[u] % W, ty = texel_of[u] / W;
    for (int k = 0; k < 9; ++k) {
      const int x2 = tx + kDx[k], y2 = ty + kDy[k];
      if (x2 >= 0 && x2 < W && y2 >= 0 && y2 < H && A[u * 9 + k] != 0)
        nb[u * 9 + k] = index[size_t(y2) * W + x2];
    }
  }
  auto multiply = [&](const std::vector<double>& v, std::vector<double>& out) {
    for (size_t u = 0; u < n; ++u) {
      double acc[4] = {0, 0, 0, 0};
      for (int k = 0; k < 9; ++k) {
        const int32_t o = nb[u * 9 + k];
        if (o < 0) continue;
        const double a = A[u * 9 + k];
        for (int c = 0; c < nch; ++c) acc[c] += a * v[size_t(o) * nch + c];
      }
      for (int c = 0; c < nch; ++c) out[u * nch + c] = acc[c];
    }
  };

  // 3. Conjugate gradients, one independent solve per channel run side by side.
  std::vector<double> r(n * nch), z(n * nch), p(n * nch), Ap(n * nch);
  multiply(x, Ap);
  for (size_t i = 0; i < r.size(); ++i) r[i] = b[i] - Ap[i];
  double rz[4] = {0, 0, 0, 0}, r0[4] = {0, 0, 0, 0};
  for (size_t u = 0; u < n; ++u)
    for (int c = 0; c < nch; ++c) {
      const size_t i = u * nch + c;
      z[i] = r[i] / A[u * 9 + kCentre];
      p[i] = z[i];
      rz[c] += r[i] * z[i];
      r0[c] += r[i] * r[i];
    }
  bool active[4];
  for (int c = 0; c < nch; ++c) active[c] = r0[c] > 0;
  for (int it = 0; it < options.max_iterations; ++it) {
    if (std::none_of(active, active + nch, [](bool a) { return a; })) break;
    report.iterations = it + 1;
    multiply(p, Ap);
    double pAp[4] = {0, 0, 0, 0};
    for (size_t u = 0; u < n; ++u)
      for (int c = 0; c < nch; ++c) pAp[c] += p[u * nch + c] * Ap[u * nch + c];
    double alpha[4] = {0, 0, 0, 0}, rr[4] = {0, 0, 0, 0}, rz_new[4] = {0, 0, 0, 0};
    for (int c = 0; c < nch; ++c) {
      if (active[c] && !(pAp[c] > 0)) active[c] = false;
      alpha[c] = active[c] ? rz[c] / pAp[c] : 0;
    }
    for (size_t u = 0; u < n; ++u)
      for (int c = 0; c < nch; ++c) {
        if (!active[c]) continue;
        const size_t i = u * nch + c;
        x[i] += alpha[c] * p[i];
        r[i] -= alpha[c] * Ap[i];
        z[i] = r[i] / A[u * 9 + kCentre];
        rr[c] += r[i] * r[i];
        rz_new[c] += r[i] * z[i];
      }
    double beta[4] = {0, 0, 0, 0};
    for (int c = 0; c < nch; ++c) {
      if (!active[c]) continue;
      if (rr[c] <= options.tolerance * options.tolerance * r0[c] || !(rz[c] > 0)) {
        active[c] = false;
        continue;
      }
      beta[c] = rz_new[c] / rz[c];
      rz[c] = rz_new[c];
    }
    for (size_t u = 0; u < n; ++u)
      for (int c = 0; c < nch; ++c)
        if (active[c]) p[u * nch + c] = z[u * nch + c] + beta[c] * p[u * nch + c];
  }

  // 4. Back into the image, clamped to the valid range.
  for (size_t u = 0; u < n; ++u)
    for (int c = 0; c < nch; ++c) {
      const double v = x[u * nch + c];
      texels[size_t(texel_of[u]) * nch + c] = std::isfinite(v)
                                                  ? std::clamp(float(v), options.min_value, options.max_value)
                                                  : texels[size_t(texel_of[u]) * nch + c];
    }
  report.error_after = sample_error(W, H, nch, xy, weight, target, texels);
  if (report_out) *report_out = report;
  return TexelFitStatus::ok;
}

}  // namespace gltfwarp
