#include "codec/encode/texture/seam_continuity.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gltfwarp {

SeamTest texture_seam_test(std::span<const TextureSampler> textures, const SeamContinuityOptions& options) {
  return [textures, options](Uv a0, Uv a1, Uv b0, Uv b1) {
    if (textures.empty() || options.samples < 1) return false;
    std::vector<float> sa, sb;
    for (const TextureSampler& t : textures) {
      const int nch = t.channels();
      if (!t.ok || nch == 0) return false;
      sa.resize(size_t(nch));
      sb.resize(size_t(nch));
      double sum = 0, peak = 0;
      for (int i = 0; i < options.samples; ++i) {
        const double w = (i + 0.5) / options.samples;
        t.sample(a0[0] + w * (a1[0] - a0[0]), a0[1] + w * (a1[1] - a0[1]), sa.data());
        t.sample(b0[0] + w * (b1[0] - b0[0]), b0[1] + w * (b1[1] - b0[1]), sb.data());
        double d = 0;
        for (int c = 0; c < nch; ++c) d = std::max(d, 255.0 * std::abs(double(sa[c]) - double(sb[c])));
        if (!(d <= options.max_peak)) return false;  // also refuses NaN
        sum += d, peak = std::max(peak, d);
      }
      if (!(sum / options.samples <= options.max_mean)) return false;
    }
    return true;
  };
}

}  // namespace gltfwarp
