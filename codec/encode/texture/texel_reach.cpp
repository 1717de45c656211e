// Texels that triangles reach, and a fill of the rest (see texel_reach.h).
#include "codec/encode/texture/texel_reach.h"

#include <algorithm>
#include <cmath>

#include <OpenImageIO/parallel.h>

#include "codec/encode/texture/atlas_fill.h"

namespace gltfwarp {

TexelReach::TexelReach(int width, int height, OIIO::ImageBuf::WrapMode wrap_s,
                       OIIO::ImageBuf::WrapMode wrap_t)
    : w_(std::max(0, width)),
      h_(std::max(0, height)),
      wrap_s_(wrap_s),
      wrap_t_(wrap_t),
      reached_(size_t(w_) * size_t(h_), 0) {}

TexelReach::TexelReach(const TextureSampler& t)
    : TexelReach(t.ok ? t.pixels.spec().width : 0, t.ok ? t.pixels.spec().height : 0, t.wrap_s, t.wrap_t) {}

void TexelReach::add_triangles(std::span<const float> uv, const std::array<double, 6>& t) {
  constexpr double kReach = 1.5;  // bilinear reads the texels within one texel of a point; half a texel more
  if (all_ || w_ == 0 || h_ == 0) return;
  for (size_t f = 0; f + 6 <= uv.size(); f += 6) {
    double x[3], y[3];
    for (int k = 0; k < 3; ++k) {
      const double u = uv[f + 2 * size_t(k)], v = uv[f + 2 * size_t(k) + 1];
      x[k] = (t[0] * u + t[1] * v + t[2]) * w_ - 0.5;  // texel centres at integers
      y[k] = (t[3] * u + t[4] * v + t[5]) * h_ - 0.5;
    }
    if (!std::isfinite(x[0] + x[1] + x[2] + y[0] + y[1] + y[2])) continue;
    const double lo_x = std::min({x[0], x[1], x[2]}) - kReach, hi_x = std::max({x[0], x[1], x[2]}) + kReach;
    const double lo_y = std::min({y[0], y[1], y[2]}) - kReach, hi_y = std::max({y[0], y[1], y[2]}) + kReach;
    if (hi_x - lo_x >= w_ || hi_y - lo_y >= h_) {  // tiles the texture: call it all reached
      all_ = true;
      std::fill(reached_.begin(), reached_.end(), uint8_t{1});
      return;
    }
    const double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    double len[3];
    for (int e = 0; e < 3; ++e) len[e] = std::hypot(x[(e + 1) % 3] - x[e], y[(e + 1) % 3] - y[e]);
    const bool degenerate = !(std::abs(area) > 1e-12);
    for (long py = long(std::ceil(lo_y)); py <= long(std::floor(hi_y)); ++py)
      for (long px = long(std::ceil(lo_x)); px <= long(std::floor(hi_x)); ++px) {
        bool in = true;
        if (!degenerate)  // signed distance to each edge, inside positive; a sliver or point keeps its box
          for (int e = 0; e < 3 && in; ++e) {
            const int a = e, b = (e + 1) % 3;
            if (len[e] == 0) continue;
            const double cross = (x[b] - x[a]) * (double(py) - y[a]) - (y[b] - y[a]) * (double(px) - x[a]);
            in = (area > 0 ? cross : -cross) / len[e] >= -kReach;
          }
        if (!in) continue;
        const int tx = wrap_texel_index(px, w_, wrap_s_), ty = wrap_texel_index(py, h_, wrap_t_);
        reached_[size_t(ty) * size_t(w_) + size_t(tx)] = 1;
      }
  }
}

uint64_t TexelReach::reached() const {
  return uint64_t(std::count(reached_.begin(), reached_.end(), uint8_t{1}));
}

void TexelReach::fill_unreached(TextureSampler& texture) const {
  if (all_ || !texture.ok || texture.pixels.spec().width != w_ || texture.pixels.spec().height != h_ ||
      texture.pixels.spec().format != OIIO::TypeDesc::FLOAT)
    return;
  const int nch = texture.channels();
  if (nch <= 0 || nch > 8) return;
  std::vector<uint8_t> empty(reached_.size());
  for (size_t i = 0; i < empty.size(); ++i) empty[i] = reached_[i] ? 0 : 1;
  if (std::find(empty.begin(), empty.end(), uint8_t{1}) == empty.end()) return;
  // The fill works on 16-bit texels: 1/65535 steps, far below 8-bit colour.
  // The conversions run row by row on every core: a 4096² source is 67M values.
  float* px = static_cast<float*>(texture.pixels.localpixels());
  const size_t row = size_t(w_) * size_t(nch);
  std::vector<uint16_t> deep(empty.size() * size_t(nch));
  OIIO::parallel_for(0, h_, [&](int y) {
    for (size_t i = size_t(y) * row; i < size_t(y + 1) * row; ++i)
      deep[i] = uint16_t(std::lround(std::clamp(px[i], 0.0f, 1.0f) * 65535.0f));
  });
  pull_push_fill(reinterpret_cast<uint8_t*>(deep.data()), w_, h_, nch, true, empty);
  OIIO::parallel_for(0, h_, [&](int y) {
    for (size_t i = size_t(y) * size_t(w_); i < size_t(y + 1) * size_t(w_); ++i)
      if (empty[i])
        for (int c = 0; c < nch; ++c)
          px[i * size_t(nch) + size_t(c)] = float(deep[i * size_t(nch) + size_t(c)]) / 65535.0f;
  });
}

TextureSampler with_unreached_filled(const TextureSampler& texture, std::span<const float> uv_faces) {
  TextureSampler out = texture;
  TexelReach reach(texture);
  reach.add_triangles(uv_faces, texture.transform);
  reach.fill_unreached(out);
  return out;
}

}  // namespace gltfwarp
