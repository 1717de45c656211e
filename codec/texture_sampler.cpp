// Viewer-like bilinear texture sampling (see texture_sampler.h).
#include "codec/texture_sampler.h"

#include <vector>

#include <tiny_gltf.h>

#include "codec/image_io.h"
#include "codec/warp.h"

namespace gltfwarp {
namespace {

// Folds a coordinate into [0, 1] as a sampler wrap mode does.
double fold(double x, OIIO::ImageBuf::WrapMode w) {
  if (w == OIIO::ImageBuf::WrapClamp) return std::clamp(x, 0.0, 1.0);
  if (w == OIIO::ImageBuf::WrapMirror) {
    const double m = x - 2.0 * std::floor(x / 2.0);
    return m <= 1.0 ? m : 2.0 - m;
  }
  return x - std::floor(x);
}

OIIO::ImageBuf::WrapMode oiio_wrap(int gl) {
  if (gl == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return OIIO::ImageBuf::WrapClamp;
  if (gl == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return OIIO::ImageBuf::WrapMirror;
  return OIIO::ImageBuf::WrapPeriodic;
}

}  // namespace

void TextureSampler::sample(double u, double v, float* out) const {
  const auto& t = transform;
  const double tu = t[0] * u + t[1] * v + t[2], tv = t[3] * u + t[4] * v + t[5];
  // OIIO's interppixel takes one wrap mode: fold per axis first when they differ.
  const bool same = wrap_s == wrap_t;
  const double fu = same ? tu : fold(tu, wrap_s), fv = same ? tv : fold(tv, wrap_t);
  pixels.interppixel_NDC(static_cast<float>(fu), static_cast<float>(fv), out,
                         same ? wrap_s : OIIO::ImageBuf::WrapClamp);
  if (srgb)
    for (int c = 0; c < std::min(3, pixels.nchannels()); ++c) out[c] = linear_to_srgb(std::clamp(out[c], 0.0f, 1.0f));
}

void load_texture_sampler(const OIIO::ImageBuf& raw, bool srgb, int gl_wrap_s, int gl_wrap_t,
                          const std::array<double, 6>& transform, TextureSampler& s) {
  s = TextureSampler{};
  OIIO::ImageSpec spec = raw.spec();
  spec.set_format(OIIO::TypeDesc::FLOAT);
  spec.x = spec.y = 0;
  s.pixels.reset(spec);
  std::vector<float> px(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  raw.get_pixels(raw.roi(), OIIO::TypeDesc::FLOAT, px.data());
  s.srgb = srgb;
  if (srgb)
    for (size_t i = 0; i < px.size(); ++i)
      if (static_cast<int>(i % spec.nchannels) < 3) px[i] = srgb_to_linear(px[i]);
  s.pixels.set_pixels(s.pixels.roi(), OIIO::TypeDesc::FLOAT, px.data());
  s.wrap_s = oiio_wrap(gl_wrap_s);
  s.wrap_t = oiio_wrap(gl_wrap_t);
  s.transform = transform;
  s.ok = spec.width > 0 && spec.height > 0;
}

std::string load_texture_sampler(std::span<const uint8_t> image_bytes, bool srgb, int gl_wrap_s, int gl_wrap_t,
                                 const std::array<double, 6>& transform, TextureSampler& out) {
  OIIO::ImageBuf raw;
  std::string err;
  if (!decode_image(image_bytes, raw, err)) return err;
  load_texture_sampler(raw, srgb, gl_wrap_s, gl_wrap_t, transform, out);
  return "";
}

}  // namespace gltfwarp
