// Texel-exact patches (texel_alignment.h).
#include "codec/encode/atlas/texel_alignment.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "format/bitstream/uvmap.h"

namespace gltfwarp {

SimilarityFit fit_texel_alignment(std::span<const double> corner_xy, std::span<const float> source_uv,
                                  std::span<const uint32_t> faces, uint32_t image_width,
                                  uint32_t image_height, double max_residual) {
  SimilarityFit none;
  if (image_width == 0 || image_height == 0 || faces.empty() || source_uv.size() != corner_xy.size())
    return none;
  std::vector<double> from, to;
  from.reserve(faces.size() * 6), to.reserve(faces.size() * 6);
  for (uint32_t f : faces) {
    if (6 * size_t(f) + 6 > corner_xy.size()) return none;
    for (int k = 0; k < 6; k += 2) {
      from.push_back(corner_xy[6 * size_t(f) + k]), from.push_back(corner_xy[6 * size_t(f) + k + 1]);
      to.push_back(double(source_uv[6 * size_t(f) + k]) * image_width);
      to.push_back(double(source_uv[6 * size_t(f) + k + 1]) * image_height);
    }
  }
  SimilarityFit fit = fit_similarity(from, to);
  if (!fit.ok || !(fit.max_residual <= max_residual) || !(std::hypot(fit.a, fit.b) > 0)) return none;
  return fit;
}

bool aligned_transform(const SimilarityFit& fit, int turn, double scale, double extent,
                       AlignedTransform& out) {
  // A mirrored layout (M) lands on the source image reflected across its
  // rows, diag(1, -1): its rotation part is then R(-angle) and nothing is
  // mirrored in the placement, since a reflection maps the lattice of texel
  // centres onto itself as a quarter turn does. Then i^turn * (a + i b): the
  // source's texel axes turned by quarter turns.
  double a = fit.a, b = fit.b, tx = fit.tx, ty = fit.ty;
  if (fit.mirror) b = -b, ty = -ty;
  for (int k = 0; k < (turn & 3); ++k) {
    a = std::exchange(b, a), a = -a;       // (a, b) -> (-b, a)
    tx = std::exchange(ty, tx), tx = -tx;  // likewise the origin
  }
  const double density = std::hypot(a, b);  // source texels per model unit
  if (!(scale > 0) || !std::isfinite(density / scale)) return false;
  // (cos_q, sin_q) near 1.7 kFineUnit: well inside the format's 2 kFineUnit
  // per component, and every bit of it used (about 1e-5 texel per texel of
  // extent).
  int32_t step = scale_step_for(density / scale / 1.7);
  for (int tries = 0; tries < 3; ++tries, ++step) {
    if (step < kMinScaleStep || step > kMaxScaleStep) return false;
    const double unit = scale * patch_scale(step);
    const double c = std::round(a / unit * kFineUnit), s = std::round(b / unit * kFineUnit);
    if (std::abs(c) > 2.0 * kFineUnit || std::abs(s) > 2.0 * kFineUnit) continue;
    if (c == 0 && s == 0) return false;
    out.scale_step = step;
    out.cos_q = int32_t(c), out.sin_q = int32_t(s);
    // atlas = i^turn (source - t) + X lands texel centres on texel centres
    // when X - i^turn t is whole: a quarter turn maps the lattice of
    // centres, (1/2, 1/2) + Z^2, onto itself.
    // In the format's 1/256 texel steps (1 is a whole texel more).
    const auto frac = [](double v) {
      return std::round((v - std::floor(v)) * kFineFracSteps) / kFineFracSteps;
    };
    out.frac_x = frac(tx), out.frac_y = frac(ty);
    out.coarse = false;
    const bool whole = (out.frac_x == 0 || out.frac_x == 1) && (out.frac_y == 0 || out.frac_y == 1);
    if (whole) {
      const uint32_t code = rotation_code_for(std::atan2(b, a));
      const int32_t coarse_step = scale_step_for(density / scale);
      double rc, rs;
      rotation_cos_sin(code, rc, rs);
      const double cs = scale * patch_scale(coarse_step);
      if (std::hypot(cs * rc - a, cs * rs - b) * extent <= 0.01) {
        out.coarse = true;
        out.rotation = code;
        out.scale_step = coarse_step;
      }
    }
    return true;
  }
  return false;
}

BlockResidue mip_block_residue(const SimilarityFit& fit, double sc, double ss, double ox, double oy,
                               int block) {
  // source = G p + t, G = [a -b; b a] M; mask frame q = R p + o. So q = Q (source - t) + o with
  // Q = R G^-1, a signed permutation for an aligned patch (both at the source's density).
  const double a = fit.a, b = fit.b, n = a * a + b * b;
  if (!(n > 0) || block <= 1) return {};
  // G^-1 = M [a b; -b a] / n (M is its own inverse).
  double gi[4] = {a / n, b / n, -b / n, a / n};
  if (fit.mirror) gi[2] = -gi[2], gi[3] = -gi[3];
  const double q[4] = {sc * gi[0] - ss * gi[2], sc * gi[1] - ss * gi[3], ss * gi[0] + sc * gi[2],
                       ss * gi[1] + sc * gi[3]};
  // Source texel (0, 0)'s centre in the mask frame: atlas texel index c + whole position.
  const double sx = 0.5 - fit.tx, sy = 0.5 - fit.ty;
  const double cx = std::floor(q[0] * sx + q[1] * sy + ox), cy = std::floor(q[2] * sx + q[3] * sy + oy);
  // Along an atlas axis the source's texels run i -> c + i (sign +) or c - i:
  // blocks line up when c = 0, or c = block - 1, (mod block).
  const auto sign = [](double u, double v) { return std::abs(u) >= std::abs(v) ? u : v; };
  const auto residue = [&](double c, double dir) {
    const long long want = dir > 0 ? 0 : block - 1;
    return int(((want - (long long)c) % block + block) % block);
  };
  return {residue(cx, sign(q[0], q[1])), residue(cy, sign(q[2], q[3]))};
}

}  // namespace gltfwarp
