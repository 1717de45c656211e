// Viewer-like bilinear texture sampling (see texture_sampler.h).
#include "codec/encode/texture/texture_sampler.h"

#include <cstdint>
#include <vector>

#include <OpenImageIO/parallel.h>

#include <tiny_gltf.h>

#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/srgb.h"

namespace gltfwarp {

int wrap_texel_index(long i, int n, OIIO::ImageBuf::WrapMode w) {
  if (w == OIIO::ImageBuf::WrapClamp) return int(std::clamp<long>(i, 0, n - 1));
  if (w == OIIO::ImageBuf::WrapMirror) {
    const long p = 2L * n, m = ((i % p) + p) % p;
    return int(m < n ? m : p - 1 - m);
  }
  return int(((i % n) + n) % n);
}

namespace {

OIIO::ImageBuf::WrapMode oiio_wrap(int gl) {
  if (gl == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return OIIO::ImageBuf::WrapClamp;
  if (gl == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return OIIO::ImageBuf::WrapMirror;
  return OIIO::ImageBuf::WrapPeriodic;
}

}  // namespace

std::string load_slot_sampler(const tinygltf::Model& model, const TextureSlot& slot, TextureSampler& out) {
  const int image = texture_image(model, slot.texture);
  if (image < 0) return "texture " + std::to_string(slot.texture) + " has no image";
  int wrap_s = 0, wrap_t = 0;
  texture_wraps(model, slot.texture, wrap_s, wrap_t);
  return load_texture_sampler(model.images[image].image, slot.color_space == ColorSpace::srgb, wrap_s, wrap_t,
                              slot.transform, out);
}

void TextureSampler::sample(double u, double v, float* out) const {
  const auto& t = transform;
  const double tu = t[0] * u + t[1] * v + t[2], tv = t[3] * u + t[4] * v + t[5];
  const int w = pixels.spec().width, h = pixels.spec().height, nch = pixels.nchannels();
  const double x = tu * w - 0.5, y = tv * h - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 1e9 || std::abs(y) > 1e9) {
    for (int c = 0; c < nch; ++c) out[c] = 0;
    return;
  }
  const double fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
  const int x0 = wrap_texel_index(long(fx), w, wrap_s), x1 = wrap_texel_index(long(fx) + 1, w, wrap_s);
  const int y0 = wrap_texel_index(long(fy), h, wrap_t), y1 = wrap_texel_index(long(fy) + 1, h, wrap_t);
  const float* px = static_cast<const float*>(pixels.localpixels());
  const float* a = px + (size_t(y0) * w + x0) * nch;
  const float* b = px + (size_t(y0) * w + x1) * nch;
  const float* d = px + (size_t(y1) * w + x0) * nch;
  const float* e = px + (size_t(y1) * w + x1) * nch;
  for (int c = 0; c < nch; ++c)
    out[c] = float((1 - ay) * ((1 - ax) * a[c] + ax * b[c]) + ay * ((1 - ax) * d[c] + ax * e[c]));
  if (srgb)
    for (int c = 0; c < std::min(3, nch); ++c) out[c] = linear_to_srgb(std::clamp(out[c], 0.0f, 1.0f));
}

void load_texture_sampler(const OIIO::ImageBuf& raw, bool srgb, int gl_wrap_s, int gl_wrap_t,
                          const std::array<double, 6>& transform, TextureSampler& s) {
  s = TextureSampler{};
  OIIO::ImageSpec spec = raw.spec();
  spec.set_format(OIIO::TypeDesc::FLOAT);
  spec.x = spec.y = 0;
  s.pixels.reset(spec);
  float* px = static_cast<float*>(s.pixels.localpixels());
  if (px) raw.get_pixels(raw.roi(), OIIO::TypeDesc::FLOAT, px);
  s.srgb = srgb;
  // Row by row in parallel: an atlas-sized page is 16M texels.
  const int nch = spec.nchannels, colour = std::min(3, nch);
  if (srgb && px) {
    OIIO::parallel_for(0, spec.height, [&](int y) {
      float* row = px + size_t(y) * spec.width * nch;
      for (int x = 0; x < spec.width; ++x)
        for (int c = 0; c < colour; ++c)
          row[size_t(x) * nch + c] = srgb_to_linear_of_pixel(row[size_t(x) * nch + c]);
    });
  }
  s.wrap_s = oiio_wrap(gl_wrap_s);
  s.wrap_t = oiio_wrap(gl_wrap_t);
  s.transform = transform;
  s.ok = spec.width > 0 && spec.height > 0;
}

std::string load_texture_sampler(std::span<const uint8_t> image_bytes, bool srgb, int gl_wrap_s,
                                 int gl_wrap_t, const std::array<double, 6>& transform, TextureSampler& out) {
  OIIO::ImageBuf raw;
  std::string err;
  if (!decode_image(image_bytes, raw, err)) return err;
  load_texture_sampler(raw, srgb, gl_wrap_s, gl_wrap_t, transform, out);
  return "";
}

}  // namespace gltfwarp
