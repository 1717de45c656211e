// Least-squares atlas texels: the texels whose bilinear reconstruction, as a
// viewer samples the atlas, best matches a target colour at dense points of
// the surface.
//
// A point-sampled atlas (each texel reads the source at its own centre) is
// blurred a second time by the viewer's bilinear filter. Solving instead for
//   min_x  sum_s w_s (sum_p B_p(s) x_p - t_s)^2 + lambda sum_p (x_p - x0_p)^2
// where B_p(s) are the bilinear weights of texel p at sample s, gives texels
// that undo that blur where the samples constrain them (the projection of
// the target onto the bilinear space, as in "Least-Squares Texture
// Baking"-style resampling; see also Unser, "Splines: a perfect fit for
// signal and image processing", IEEE SPM 1999, on fitting rather than
// interpolating a spline's coefficients). The normal equations have a 3x3
// texel stencil; they are solved by conjugate gradients with a Jacobi
// preconditioner (Saad, "Iterative Methods for Sparse Linear Systems", 9.2),
// warm-started from x0, with a fixed iteration cap.
//
// Texel i of a row of `width` covers [i, i + 1) and has its centre at
// i + 0.5 (texel coordinates = UV * size), as GPUs sample; the reconstruction
// clamps texel indices to the image (CLAMP_TO_EDGE, the atlas's sampler).
// Texels that no sample's stencil reaches are not unknowns: they keep x0.
#pragma once

#include <cstdint>
#include <span>

namespace gltfwarp {

struct TexelFitOptions {
  int max_iterations = 32;     // conjugate-gradient iterations at most (the warm start is close)
  double tolerance = 1e-4;     // stop when every channel's residual fell by this factor
  double regularizer = 0.002;  // lambda, relative to the mean diagonal of the normal equations:
                               // pulls weakly-seen texels (a patch's outer ring) toward x0
  float min_value = 0;         // the fitted texels are clamped to [min_value, max_value]
  float max_value = 1;
};

struct TexelFitReport {
  uint64_t samples = 0;        // samples with a positive weight
  uint64_t fitted_texels = 0;  // unknowns: texels some sample's stencil reaches
  int iterations = 0;
  double error_before = 0;  // weighted squared error of x0's reconstruction (sum over channels)
  double error_after = 0;   // the same for the fitted, clamped texels
  double gain_db() const;   // 10 log10(before / after); 0 when nothing was fitted
};

enum class TexelFitStatus : uint8_t { ok = 0, bad_input };

// texels: width * height * channels floats, row-major, interleaved; in: x0
// (the warm start), out: the fit. sample_xy: 2 per sample, texel
// coordinates; sample_weight: 1 per sample (>= 0); sample_target:
// `channels` per sample. unknown (optional, width * height flags): set to 1
// where a texel was an unknown of the fit, untouched elsewhere.
TexelFitStatus fit_texels(uint32_t width, uint32_t height, int channels, std::span<const float> sample_xy,
                          std::span<const float> sample_weight, std::span<const float> sample_target,
                          std::span<float> texels, const TexelFitOptions& options = {},
                          TexelFitReport* report = nullptr, std::span<uint8_t> unknown = {});

}  // namespace gltfwarp
