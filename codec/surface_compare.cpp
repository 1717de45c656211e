#include "codec/surface_compare.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <OpenImageIO/imagebuf.h>

#include "codec/corner_match.h"
#include "codec/image_io.h"
#include "codec/warp.h"
#include "format/gltf_materials.h"
#include "format/gltf_primitive.h"

namespace gltfwarp {
namespace {

struct SlotImage {
  OIIO::ImageBuf pixels;  // float; colour channels in linear light for sRGB slots
  OIIO::ImageBuf::WrapMode wrap_s = OIIO::ImageBuf::WrapPeriodic, wrap_t = OIIO::ImageBuf::WrapPeriodic;
  bool srgb = false;
  std::array<double, 6> transform{1, 0, 0, 0, 1, 0};
  bool ok = false;
};

// Folds a coordinate into [0, 1] as a sampler wrap mode does.
double fold(double x, OIIO::ImageBuf::WrapMode w) {
  if (w == OIIO::ImageBuf::WrapClamp) return std::clamp(x, 0.0, 1.0);
  if (w == OIIO::ImageBuf::WrapMirror) {
    const double m = x - 2.0 * std::floor(x / 2.0);
    return m <= 1.0 ? m : 2.0 - m;
  }
  return x - std::floor(x);
}

// Bilinear sample with glTF's per-axis wrap (OIIO's interppixel takes one mode).
void sample(const SlotImage& s, double u, double v, float* out) {
  const bool same = s.wrap_s == s.wrap_t;
  const double fu = same ? u : fold(u, s.wrap_s), fv = same ? v : fold(v, s.wrap_t);
  s.pixels.interppixel_NDC(static_cast<float>(fu), static_cast<float>(fv), out,
                           same ? s.wrap_s : OIIO::ImageBuf::WrapClamp);
  if (s.srgb)
    for (int c = 0; c < std::min(3, s.pixels.nchannels()); ++c) out[c] = linear_to_srgb(std::clamp(out[c], 0.0f, 1.0f));
}

OIIO::ImageBuf::WrapMode oiio_wrap(int gl) {
  if (gl == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return OIIO::ImageBuf::WrapClamp;
  if (gl == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return OIIO::ImageBuf::WrapMirror;
  return OIIO::ImageBuf::WrapPeriodic;
}

SlotImage slot_image(const tinygltf::Model& m, int material, const std::string& key) {
  SlotImage s;
  for (const auto& slot : texture_slots(m, material)) {
    if (slot.name() != key || slot.tex_coord != 0) continue;
    const int img = texture_image(m, slot.texture);
    if (img < 0) return s;
    std::string err;
    OIIO::ImageBuf raw;
    if (!decode_image(m.images[img].image, raw, err)) return s;
    // A GPU filters sRGB textures in linear light: interpolate there too.
    s.srgb = slot.color_space == ColorSpace::srgb;
    OIIO::ImageSpec spec = raw.spec();
    spec.set_format(OIIO::TypeDesc::FLOAT);
    s.pixels.reset(spec);
    std::vector<float> px(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
    raw.get_pixels(raw.roi(), OIIO::TypeDesc::FLOAT, px.data());
    if (s.srgb)
      for (size_t i = 0; i < px.size(); ++i)
        if (static_cast<int>(i % spec.nchannels) < 3) px[i] = srgb_to_linear(px[i]);
    s.pixels.set_pixels(s.pixels.roi(), OIIO::TypeDesc::FLOAT, px.data());
    const int sampler = m.textures[slot.texture].sampler;
    if (sampler >= 0 && static_cast<size_t>(sampler) < m.samplers.size()) {
      s.wrap_s = oiio_wrap(m.samplers[sampler].wrapS);
      s.wrap_t = oiio_wrap(m.samplers[sampler].wrapT);
    }
    s.transform = slot.transform;
    s.ok = true;
    return s;
  }
  return s;
}


}  // namespace

SurfaceComparison compare_surface(const tinygltf::Model& src, const tinygltf::Model& dec,
                                  const SurfaceCompareOptions& options) {
  SurfaceComparison r;
  double sq = 0, weight = 0;
  if (src.meshes.size() != dec.meshes.size()) {
    r.error = "the scenes have different mesh counts";
    return r;
  }
  for (size_t mi = 0; mi < src.meshes.size(); ++mi) {
    if (src.meshes[mi].primitives.size() != dec.meshes[mi].primitives.size()) {
      r.error = "mesh " + std::to_string(mi) + " has a different primitive count";
      return r;
    }
    for (size_t pi = 0; pi < src.meshes[mi].primitives.size(); ++pi) {
      const auto& sp = src.meshes[mi].primitives[pi];
      const auto& dp = dec.meshes[mi].primitives[pi];
      if (!is_triangle_mode(sp.mode)) continue;
      SlotImage si = slot_image(src, sp.material, options.slot), di = slot_image(dec, dp.material, options.slot);
      if (!si.ok || !di.ok) continue;
      PrimitiveGeometry sg, dg;
      if (!read_primitive(src, sp, sg).empty() || !read_primitive(dec, dp, dg).empty()) continue;
      const VertexAttribute *spos = sg.find("POSITION"), *dpos = dg.find("POSITION");
      const VertexAttribute *suv = sg.find("TEXCOORD_0"), *duv = dg.find("TEXCOORD_0");
      if (!spos || !dpos || !suv || !duv) continue;
      // Tolerance: a Draco 14-bit step of the model's extent, generously.
      double lo = 1e300, hi = -1e300;
      for (size_t e = 0; e < spos->count(); ++e)
        for (int i = 0; i < 3; ++i) {
          lo = std::min<double>(lo, spos->get(e, i));
          hi = std::max<double>(hi, spos->get(e, i));
        }
      const double tol = (hi - lo) / 16383.0 * 2.0 + 1e-9;
      const CornerMatch match = match_corners(spos->to_floats(), sg.triangles, dpos->to_floats(), dg.triangles, tol);
      r.unmatched_faces += match.unmatched_faces;
      r.primitives++;
      const int nch = std::min(si.pixels.nchannels(), di.pixels.nchannels());
      const int channels = std::min(nch, 3);  // colour only; alpha is compared by its effect elsewhere
      std::vector<float> a(static_cast<size_t>(si.pixels.nchannels())), b(static_cast<size_t>(di.pixels.nchannels()));
      const int k = std::max(1, options.samples_per_face);
      for (size_t f = 0; f < dg.triangles.size() / 3; ++f) {
        const uint32_t sc0 = match.source_corner[3 * f];
        if (sc0 == 0 && match.source_corner[3 * f + 1] == 0) continue;  // unmatched
        for (int s = 0; s < k; ++s) {
          // Interior points spread over the triangle (low-discrepancy weights).
          const double u = (s + 0.5) / k, v = std::fmod(0.618034 * (s + 1), 1.0);
          double w0 = 1 - std::sqrt(u), w1 = std::sqrt(u) * (1 - v), w2 = std::sqrt(u) * v;
          double su = 0, sv = 0, du = 0, dv = 0;
          const double w[3] = {w0, w1, w2};
          for (int c = 0; c < 3; ++c) {
            const uint32_t sv_id = sg.triangles[match.source_corner[3 * f + c]];
            const uint32_t dv_id = dg.triangles[3 * f + c];
            su += w[c] * suv->get(sv_id, 0);
            sv += w[c] * suv->get(sv_id, 1);
            du += w[c] * duv->get(dv_id, 0);
            dv += w[c] * duv->get(dv_id, 1);
          }
          const auto& t = si.transform;
          const double tu = t[0] * su + t[1] * sv + t[2], tv = t[3] * su + t[4] * sv + t[5];
          sample(si, tu, tv, a.data());
          sample(di, du, dv, b.data());
          for (int c = 0; c < channels; ++c) {
            const double d = 255.0 * (a[c] - b[c]);
            sq += d * d;
            weight += 1;
            r.max_abs = std::max(r.max_abs, std::abs(d));
          }
          r.samples++;
        }
      }
    }
  }
  if (weight == 0) {
    r.error = "no textured primitive to compare";
    return r;
  }
  r.rmse = std::sqrt(sq / weight);
  r.psnr = r.rmse > 0 ? 20.0 * std::log10(255.0 / r.rmse) : std::numeric_limits<double>::infinity();
  return r;
}

}  // namespace gltfwarp
