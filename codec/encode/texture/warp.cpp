// Texture warping into the atlas (sources in warp.h).
#include "codec/encode/texture/warp.h"

#include <OpenImageIO/filter.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

#include <unistd.h>

#include "codec/core/parallel.h"
#include "codec/encode/texture/atlas_fill.h"
#include "codec/encode/texture/srgb.h"
#include "codec/encode/texture/texture_sampler.h"

namespace gltfwarp {

using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::ROI;
using OIIO::TypeDesc;

WrapMode wrap_from_gltf(int gl_enum) {
  switch (gl_enum) {
    case 33648:
      return WrapMode::mirrored_repeat;
    case 33071:
      return WrapMode::clamp_to_edge;
    default:
      return WrapMode::repeat;
  }
}

const char* to_string(WarpStatus s) {
  switch (s) {
    case WarpStatus::ok:
      return "ok";
    case WarpStatus::bad_input:
      return "bad input";
    case WarpStatus::texture_error:
      return "texture error";
  }
  return "unknown";
}

namespace {

// A triangle of the page in atlas texel coordinates, with the affine map to
// the (transformed) source UV.
struct Tri {
  double x[3], y[3];  // atlas texel coordinates of the corners
  double s[3], t[3];  // source UV of the corners (transform applied)
  float dsdx, dtdx, dsdy, dtdy;
  uint32_t prim, face;
  bool magnifies;  // one atlas texel spans at most one source texel
  // The face lies on the source's texel grid (texel_alignment.h): its map is
  // a quarter turn or a reflection, one source texel per atlas texel, and
  // atlas texel centres go to source texel centres. Its texels, and the
  // gutter texels it owns, copy the source texel under their centres by
  // its affine map (extended past the face: the gutter then holds what the
  // source holds beside the face, and a viewer's bilinear filter reads the
  // same neighbours there as on the source).
  bool exact;
  double sx0, sy0, sa, sb, sc, sd;  // source texel = (sx0, sy0) + [sa sb; sc sd] * (atlas - corner 0)
};

// A 2x2 map that is a signed permutation (a quarter turn or a reflection)
// to `tol`.
bool signed_permutation(double a, double b, double c, double d, double tol) {
  const auto one = [tol](double v) { return std::abs(std::abs(v) - 1) <= tol; };
  const auto zero = [tol](double v) { return std::abs(v) <= tol; };
  return (one(a) && one(d) && zero(b) && zero(c)) || (zero(a) && zero(d) && one(b) && one(c));
}

OIIO::ImageBuf::WrapMode to_imagebuf_wrap(WrapMode w) {
  switch (w) {
    case WrapMode::clamp_to_edge:
      return OIIO::ImageBuf::WrapClamp;
    case WrapMode::mirrored_repeat:
      return OIIO::ImageBuf::WrapMirror;
    default:
      return OIIO::ImageBuf::WrapPeriodic;
  }
}

// Catmull-Rom interpolation of a linear float image (texel centres at
// half-integers, as the texture system and glTF viewers place them), with
// the kernel from OIIO's filter library.
class CubicSampler {
 public:
  CubicSampler(const std::vector<float>& px, int w, int h, int nch, WrapMode ws, WrapMode wt)
      : px_(px),
        w_(w),
        h_(h),
        nch_(nch),
        ws_(to_imagebuf_wrap(ws)),
        wt_(to_imagebuf_wrap(wt)),
        kernel_(OIIO::Filter1D::create("catmull-rom", 4.0f), &OIIO::Filter1D::destroy) {}

  void sample(float s, float t, float* out) const {
    const double x = double(s) * w_ - 0.5, y = double(t) * h_ - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const int ix = int(fx), iy = int(fy);
    // OIIO's filters are not normalised: divide by the taps' sums.
    float wx[4], wy[4], sx = 0, sy = 0;
    for (int k = 0; k < 4; ++k) {
      wx[k] = (*kernel_)(float(x - (fx + k - 1)));
      wy[k] = (*kernel_)(float(y - (fy + k - 1)));
      sx += wx[k], sy += wy[k];
    }
    for (int k = 0; k < 4; ++k) wx[k] /= sx, wy[k] /= sy;
    int cx[4];
    for (int k = 0; k < 4; ++k) cx[k] = wrap_texel_index(ix + k - 1, w_, ws_);
    float acc[4] = {0, 0, 0, 0};
    float lo[4] = {1e30f, 1e30f, 1e30f, 1e30f}, hi[4] = {-1e30f, -1e30f, -1e30f, -1e30f};
    for (int j = 0; j < 4; ++j) {
      const float* row = &px_[size_t(wrap_texel_index(iy + j - 1, h_, wt_)) * w_ * nch_];
      for (int i = 0; i < 4; ++i) {
        const float wgt = wx[i] * wy[j];
        const float* p = row + size_t(cx[i]) * nch_;
        const bool inner = (i == 1 || i == 2) && (j == 1 || j == 2);
        for (int c = 0; c < nch_; ++c) {
          acc[c] += wgt * p[c];
          if (inner) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
        }
      }
    }
    // No overshoot beyond the four nearest texels: the cubic's ringing at
    // hard edges would add colours (and bytes) that the source never had.
    for (int c = 0; c < nch_; ++c) out[c] = std::clamp(acc[c], lo[c], hi[c]);
  }

 private:
  const std::vector<float>& px_;
  int w_, h_, nch_;
  OIIO::ImageBuf::WrapMode ws_, wt_;
  std::unique_ptr<OIIO::Filter1D, void (*)(OIIO::Filter1D*)> kernel_;
};

// Barycentric coordinates of the point of the triangle closest to p
// (Ericson, "Real-Time Collision Detection", 5.1.5), in 2D.
void closest_barycentric(const Tri& tr, double px, double py, double b[3]) {
  const double ax = tr.x[0], ay = tr.y[0];
  const double abx = tr.x[1] - ax, aby = tr.y[1] - ay, acx = tr.x[2] - ax, acy = tr.y[2] - ay;
  const double apx = px - ax, apy = py - ay;
  const double d1 = abx * apx + aby * apy, d2 = acx * apx + acy * apy;
  if (d1 <= 0 && d2 <= 0) {
    b[0] = 1, b[1] = 0, b[2] = 0;
    return;
  }
  const double bpx = px - tr.x[1], bpy = py - tr.y[1];
  const double d3 = abx * bpx + aby * bpy, d4 = acx * bpx + acy * bpy;
  if (d3 >= 0 && d4 <= d3) {
    b[0] = 0, b[1] = 1, b[2] = 0;
    return;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    b[0] = 1 - v, b[1] = v, b[2] = 0;
    return;
  }
  const double cpx = px - tr.x[2], cpy = py - tr.y[2];
  const double d5 = abx * cpx + aby * cpy, d6 = acx * cpx + acy * cpy;
  if (d6 >= 0 && d5 <= d6) {
    b[0] = 0, b[1] = 0, b[2] = 1;
    return;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    b[0] = 1 - w, b[1] = 0, b[2] = w;
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    b[0] = 0, b[1] = 1 - w, b[2] = w;
    return;
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  b[0] = 1 - v - w, b[1] = v, b[2] = w;
}

struct Vec3 {
  double x, y, z;
};
Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 normalized(Vec3 a) {
  const double l = std::sqrt(dot(a, a));
  return l > 0 ? (1.0 / l) * a : a;
}

// The TBN frame a viewer builds from interpolated per-vertex attributes
// (three.js / glTF sample viewer): normalize(T), normalize(w * cross(N, T)), normalize(N).
void frame_at(const WarpPrimitive& p, std::span<const float> tangents, uint32_t face, const double b[3],
              Vec3& T, Vec3& B, Vec3& N) {
  Vec3 t{0, 0, 0}, n{0, 0, 0};
  double w = 0;
  for (int k = 0; k < 3; ++k) {
    const size_t c = 3 * size_t(face) + k;
    t = t + b[k] * Vec3{tangents[4 * c], tangents[4 * c + 1], tangents[4 * c + 2]};
    w += b[k] * tangents[4 * c + 3];
    n = n + b[k] * Vec3{p.normals[3 * c], p.normals[3 * c + 1], p.normals[3 * c + 2]};
  }
  N = normalized(n);
  T = normalized(t);
  B = normalized((w < 0 ? -1.0 : 1.0) * cross(N, T));
}

// Solves [T B N] x = v (Cramer's rule); falls back to v when singular.
Vec3 solve_frame(Vec3 T, Vec3 B, Vec3 N, Vec3 v) {
  const double det = dot(T, cross(B, N));
  if (std::abs(det) < 1e-12) return v;
  return {dot(v, cross(B, N)) / det, dot(T, cross(v, N)) / det, dot(T, cross(B, v)) / det};
}

OIIO::TextureOpt::Wrap to_oiio(WrapMode w) {
  switch (w) {
    case WrapMode::mirrored_repeat:
      return OIIO::TextureOpt::WrapMirror;
    case WrapMode::clamp_to_edge:
      return OIIO::TextureOpt::WrapClamp;
    default:
      return OIIO::TextureOpt::WrapPeriodic;
  }
}

std::string unique_temp_path(const std::string& dir) {
  static std::atomic<uint64_t> counter{0};
  std::random_device rd;
  const std::filesystem::path base =
      dir.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(dir);
  std::ostringstream name;
  name << "gltfwarp-" << ::getpid() << "-" << counter++ << "-" << std::hex << rd() << rd() << ".exr";
  return (base / name.str()).string();
}

// Whether the staged source keeps its linear texels in memory (cubic
// lookups, the fit): up to 4096^2 texels.
bool keeps_linear(const WarpOptions& options, int width, int height) {
  return options.cubic_magnification && size_t(width) * size_t(height) <= (size_t(1) << 24);
}

// Which channels carry sRGB colour: all but alpha (channel 3 of 4, 1 of 2).
bool is_color_channel(int c, int nch) { return nch >= 3 ? c < 3 : c < 1; }

// The source as a viewer samples it when magnifying: bilinear on the linear
// texels, texel indices wrapped per axis (texture_sampler.h).
void bilinear(const std::vector<float>& px, int w, int h, int nch, OIIO::ImageBuf::WrapMode ws,
              OIIO::ImageBuf::WrapMode wt, double s, double t, float* out) {
  const double x = s * w - 0.5, y = t * h - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 1e9 || std::abs(y) > 1e9) {
    for (int c = 0; c < nch; ++c) out[c] = 0;
    return;
  }
  const double fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
  const int x0 = wrap_texel_index(long(fx), w, ws), x1 = wrap_texel_index(long(fx) + 1, w, ws);
  const int y0 = wrap_texel_index(long(fy), h, wt), y1 = wrap_texel_index(long(fy) + 1, h, wt);
  const float* a = &px[(size_t(y0) * w + x0) * nch];
  const float* b = &px[(size_t(y0) * w + x1) * nch];
  const float* d = &px[(size_t(y1) * w + x0) * nch];
  const float* e = &px[(size_t(y1) * w + x1) * nch];
  for (int c = 0; c < nch; ++c)
    out[c] = float((1 - ay) * ((1 - ax) * a[c] + ax * b[c]) + ay * ((1 - ax) * d[c] + ax * e[c]));
}

struct FitInput {
  const std::vector<Tri>& tris;
  std::span<const WarpPrimitive> prims;
  const std::vector<float>& linear;  // the source, linear values
  int sw, sh, nch, W, H;
  bool srgb, deep;
  const WarpOptions& options;
};

// Least-squares texels over the page (texel_fit.h), strip by strip: each
// strip of rows is solved with a few rows of halo on either side (the
// normal equations couple texels one row apart, so the halo's influence on
// the kept rows is small) and only its own rows are kept. The warm start
// is read from a copy of the point-sampled page, so strips run in any order
// and the result does not depend on the thread count. Then every gutter
// texel that no sample reached copies its nearest fitted or covered texel,
// as the warp's own dilation did.
void fit_atlas(const FitInput& in, uint8_t* pixels, const std::vector<uint8_t>& kind, size_t thread_cap,
               TexelFitReport& total) {
  const int W = in.W, H = in.H, nch = in.nch;
  const WarpOptions& o = in.options;
  constexpr int kStrip = 64, kHalo = 4;
  const int strips = (H + kStrip - 1) / kStrip;
  const double qmax = in.deep ? 65535.0 : 255.0;
  const size_t texel_bytes = size_t(nch) * (in.deep ? 2 : 1);
  const std::vector<uint8_t> warm(pixels, pixels + size_t(W) * H * texel_bytes);
  std::vector<uint8_t> unknown(size_t(W) * H, 0);
  float lut[256];
  for (int i = 0; i < 256; ++i) lut[i] = in.srgb ? srgb_to_linear(float(i) / 255.0f) : float(i) / 255.0f;
  auto load = [&](size_t texel, int c) -> float {
    const uint8_t* p = &warm[texel * texel_bytes];
    if (!in.deep) return is_color_channel(c, nch) ? lut[p[c]] : float(p[c]) / 255.0f;
    const float v = float(reinterpret_cast<const uint16_t*>(p)[c] / 65535.0);
    return in.srgb && is_color_channel(c, nch) ? srgb_to_linear(v) : v;
  };
  // Sample weights: per face its area (3D when given, else source texels),
  // scaled so that a fully covered texel's samples weigh about 1 overall.
  std::vector<double> face_weight(in.tris.size());
  double weight_sum = 0, atlas_area = 0;
  std::vector<std::vector<uint32_t>> strip_tris(strips);
  for (size_t i = 0; i < in.tris.size(); ++i) {
    const Tri& tr = in.tris[i];
    const WarpPrimitive& p = in.prims[tr.prim];
    const double area_atlas =
        0.5 * std::abs((tr.x[1] - tr.x[0]) * (tr.y[2] - tr.y[0]) - (tr.x[2] - tr.x[0]) * (tr.y[1] - tr.y[0]));
    const double area_source =
        0.5 *
        std::abs((tr.s[1] - tr.s[0]) * (tr.t[2] - tr.t[0]) - (tr.s[2] - tr.s[0]) * (tr.t[1] - tr.t[0])) *
        in.sw * in.sh;
    face_weight[i] = p.face_area.size() > tr.face ? double(p.face_area[tr.face]) : area_source;
    if (!std::isfinite(face_weight[i]) || face_weight[i] < 0) face_weight[i] = 0;
    weight_sum += face_weight[i];
    atlas_area += area_atlas;
    const double y0 = std::min({tr.y[0], tr.y[1], tr.y[2]}), y1 = std::max({tr.y[0], tr.y[1], tr.y[2]});
    const int r0 = std::max(0, int(std::floor(y0)) - kHalo - 1),
              r1 = std::min(H - 1, int(std::ceil(y1)) + kHalo);
    for (int b = r0 / kStrip; b <= r1 / kStrip; ++b) strip_tris[b].push_back(uint32_t(i));
  }
  const double weight_scale = weight_sum > 0 ? atlas_area / weight_sum : 0;
  const auto ws = to_imagebuf_wrap(o.wrap_s), wt = to_imagebuf_wrap(o.wrap_t);
  struct Scratch {
    std::vector<float> xy, weight, target, texels;
    std::vector<uint8_t> mask;
    TexelFitReport report;
  };
  std::vector<Scratch> scratch(worker_count(size_t(strips), thread_cap));
  run_in_parallel(size_t(strips), scratch.size(), [&](size_t strip, size_t worker) {
    // Named references, not a structured binding: lambdas below capture them
    // (clang before 16 cannot capture a binding).
    Scratch& sc = scratch[worker];
    std::vector<float>& xy = sc.xy;
    std::vector<float>& weight = sc.weight;
    std::vector<float>& target = sc.target;
    std::vector<float>& texels = sc.texels;
    std::vector<uint8_t>& mask = sc.mask;
    TexelFitReport& mine = sc.report;
    const int b = int(strip);
    const int y0 = b * kStrip, y1 = std::min(H, y0 + kStrip);
    const int r0 = std::max(0, y0 - kHalo), r1 = std::min(H, y1 + kHalo), rows = r1 - r0;
    xy.clear(), weight.clear(), target.clear();
    float value[4];
    for (uint32_t id : strip_tris[b]) {
      const Tri& tr = in.tris[id];
      if (!(face_weight[id] > 0)) continue;
      const double area_atlas = 0.5 * std::abs((tr.x[1] - tr.x[0]) * (tr.y[2] - tr.y[0]) -
                                               (tr.x[2] - tr.x[0]) * (tr.y[1] - tr.y[0]));
      const double area_source =
          0.5 *
          std::abs((tr.s[1] - tr.s[0]) * (tr.t[2] - tr.t[0]) - (tr.s[2] - tr.s[0]) * (tr.t[1] - tr.t[0])) *
          in.sw * in.sh;
      const double dense = std::max(area_atlas, area_source) * o.fit_samples_per_texel;
      const int n = std::clamp(int(std::ceil(std::sqrt(dense))), 2, 96);
      const float w = float(face_weight[id] * weight_scale / (double(n) * n));
      for_each_surface_point(n, [&](double b0, double b1, double b2) {
        const double x = b0 * tr.x[0] + b1 * tr.x[1] + b2 * tr.x[2];
        const double y = b0 * tr.y[0] + b1 * tr.y[1] + b2 * tr.y[2];
        if (y < r0 || y >= r1) return;
        bilinear(in.linear, in.sw, in.sh, nch, ws, wt, b0 * tr.s[0] + b1 * tr.s[1] + b2 * tr.s[2],
                 b0 * tr.t[0] + b1 * tr.t[1] + b2 * tr.t[2], value);
        xy.push_back(float(x)), xy.push_back(float(y - r0));
        // sRGB slots: the error that shows is in encoded values, so each
        // sample weighs the squared slope of the sRGB curve at its colour
        // (the fit is linear in linear light, the viewer's filter space).
        float slope = 1;
        if (in.srgb) {
          slope = 0;
          const int colours = std::min(nch, 3);
          for (int c = 0; c < colours; ++c) {
            const float v = std::max(value[c], 0.0031308f);
            const float d = 1.055f / 2.4f * std::pow(v, 1.0f / 2.4f - 1.0f);
            slope += d * d / float(colours);
          }
        }
        weight.push_back(w * slope);
        for (int c = 0; c < nch; ++c) target.push_back(value[c]);
      });
    }
    if (weight.empty()) return;
    texels.resize(size_t(W) * rows * nch);
    for (int y = r0; y < r1; ++y)
      for (int x = 0; x < W; ++x)
        for (int c = 0; c < nch; ++c) texels[(size_t(y - r0) * W + x) * nch + c] = load(size_t(y) * W + x, c);
    mask.assign(size_t(W) * rows, 0);
    TexelFitReport r;
    fit_texels(uint32_t(W), uint32_t(rows), nch, xy, weight, target, texels, o.fit, &r, mask);
    mine.samples += r.samples, mine.fitted_texels += r.fitted_texels;
    mine.iterations = std::max(mine.iterations, r.iterations);
    mine.error_before += r.error_before, mine.error_after += r.error_after;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < W; ++x) {
        const size_t at = size_t(y - r0) * W + x;
        if (!mask[at]) continue;
        unknown[size_t(y) * W + x] = 1;
        uint8_t* dst = pixels + (size_t(y) * W + x) * texel_bytes;
        for (int c = 0; c < nch; ++c) {
          float v = texels[at * nch + c];
          if (in.srgb && is_color_channel(c, nch)) v = linear_to_srgb(std::max(v, 0.0f));
          const double q = std::round(std::clamp(double(v), 0.0, 1.0) * qmax);
          if (in.deep)
            reinterpret_cast<uint16_t*>(dst)[c] = uint16_t(q);
          else
            dst[c] = uint8_t(q);
        }
      }
  });
  for (const Scratch& sc : scratch) {
    const TexelFitReport& mine = sc.report;
    total.samples += mine.samples, total.fitted_texels += mine.fitted_texels;
    total.iterations = std::max(total.iterations, mine.iterations);
    total.error_before += mine.error_before, total.error_after += mine.error_after;
  }

  // Gutter texels the fit did not reach follow their nearest kept texel.
  const int g = int(o.gutter);
  const std::vector<uint8_t> fitted(pixels, pixels + size_t(W) * H * texel_bytes);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t at = size_t(y) * W + x;
      if (kind[at] != 2 || unknown[at]) continue;
      long best = 1L << 40;
      size_t from = at;
      for (int yy = std::max(0, y - g); yy <= std::min(H - 1, y + g); ++yy)
        for (int xx = std::max(0, x - g); xx <= std::min(W - 1, x + g); ++xx) {
          const size_t k = size_t(yy) * W + xx;
          if (kind[k] != 1 && !unknown[k]) continue;
          const long d = long(yy - y) * (yy - y) + long(xx - x) * (xx - x);
          if (d < best) best = d, from = k;
        }
      if (from != at)
        std::copy(&fitted[from * texel_bytes], &fitted[from * texel_bytes] + texel_bytes,
                  pixels + at * texel_bytes);
    }
}

}  // namespace

StagedSource::~StagedSource() {
  if (!path.empty()) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
}

std::shared_ptr<const StagedSource> stage_source(const ImageBuf& source, const WarpOptions& options,
                                                 std::string& error) {
  const ImageSpec& sspec = source.spec();
  const int nch = sspec.nchannels;
  if (!source.initialized() || sspec.width <= 0 || sspec.height <= 0 || nch < 1 || nch > 4) {
    error = "source image is empty or has an unsupported channel count";
    return nullptr;
  }
  const bool srgb = options.encoding == SlotEncoding::srgb;
  const int sw = sspec.width, sh = sspec.height;
  const bool deep = sspec.format.size() > 1;  // uint16, half, float sources
  auto staged = std::make_shared<StagedSource>();
  staged->path = unique_temp_path(options.temp_dir);
  staged->width = sw, staged->height = sh, staged->channels = nch;
  staged->encoding = options.encoding;
  const bool keep_linear = keeps_linear(options, sw, sh);
  std::vector<float>& linear = staged->linear;
  if (keep_linear) linear.resize(size_t(sw) * sh * nch);
  ImageBuf stage(ImageSpec(sw, sh, nch, deep ? TypeDesc::FLOAT : TypeDesc::HALF));
  std::vector<float> rows;
  const int chunk = 64;
  for (int y0 = sspec.y; y0 < sspec.y + sh; y0 += chunk) {
    const int y1 = std::min(sspec.y + sh, y0 + chunk);
    const ROI roi(sspec.x, sspec.x + sw, y0, y1, 0, 1, 0, nch);
    rows.resize(size_t(sw) * (y1 - y0) * nch);
    if (!source.get_pixels(roi, TypeDesc::FLOAT, rows.data())) {
      error = "cannot read source pixels: " + source.geterror();
      return nullptr;
    }
    if (srgb) {
      for (size_t i = 0; i < rows.size(); ++i) {
        if (!is_color_channel(int(i % nch), nch)) continue;
        rows[i] = srgb_to_linear_of_pixel(rows[i]);
      }
    }
    const ROI droi(0, sw, y0 - sspec.y, y1 - sspec.y, 0, 1, 0, nch);
    stage.set_pixels(droi, TypeDesc::FLOAT, rows.data());
    if (keep_linear) std::copy(rows.begin(), rows.end(), linear.begin() + size_t(y0 - sspec.y) * sw * nch);
  }
  ImageSpec config(sw, sh, nch, deep ? TypeDesc::FLOAT : TypeDesc::HALF);
  config.tile_width = 64;
  config.tile_height = 64;
  config.tile_depth = 1;
  config.attribute("maketx:filtername", "box");
  config.attribute("maketx:hash", 0);  // no SHA-1 of a throwaway file
  config.attribute("maketx:compute_average", 0);
  config.attribute("compression", "none");  // staged for a few reads, skip zlib
  std::ostringstream err;
  if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, stage, staged->path, config,
                                        &err)) {
    error = "cannot stage the source texture: " + err.str() + OIIO::geterror();
    return nullptr;
  }
  return staged;
}

WarpStatus warp_texture(const ImageBuf& source, std::span<const WarpPrimitive> prims, uint32_t atlas_width,
                        uint32_t atlas_height, const WarpOptions& options, ImageBuf& out,
                        WarpReport* report_out, const StagedSource* staged) {
  const auto t0 = std::chrono::steady_clock::now();
  WarpReport report;
  auto fail = [&](WarpStatus s, std::string msg) {
    report.error = std::move(msg);
    if (report_out) *report_out = report;
    return s;
  };
  const ImageSpec& sspec = source.spec();
  const int nch = sspec.nchannels;
  if (!source.initialized() || sspec.width <= 0 || sspec.height <= 0 || nch < 1 || nch > 4)
    return fail(WarpStatus::bad_input, "source image is empty or has an unsupported channel count");
  if (atlas_width == 0 || atlas_height == 0 || atlas_width > 65536 || atlas_height > 65536)
    return fail(WarpStatus::bad_input, "bad atlas size");
  const bool normal_map = options.encoding == SlotEncoding::normal;
  if (normal_map && nch < 3) return fail(WarpStatus::bad_input, "normal map with fewer than 3 channels");
  for (const WarpPrimitive& p : prims) {
    const size_t corners = p.atlas_uv.size() / 2;
    if (p.atlas_uv.size() % 6 != 0 || p.source_uv.size() != p.atlas_uv.size())
      return fail(WarpStatus::bad_input, "source_uv and atlas_uv must hold 2 floats per corner");
    if (!p.page_of_face.empty() && p.page_of_face.size() != corners / 3)
      return fail(WarpStatus::bad_input, "page_of_face must hold one page per face");
    if (normal_map && (p.normals.size() != 3 * corners || p.old_tangents.size() != 4 * corners ||
                       p.new_tangents.size() != 4 * corners))
      return fail(WarpStatus::bad_input, "normal map warp needs normals and both tangent frames");
  }

  // 1. The source staged (stage_source), here or by the caller for several warps.
  std::shared_ptr<const StagedSource> own;
  if (!staged) {
    std::string why;
    own = stage_source(source, options, why);
    if (!own) return fail(WarpStatus::texture_error, why);
    staged = own.get();
  }
  const int sw = sspec.width, sh = sspec.height;
  const bool srgb = options.encoding == SlotEncoding::srgb;
  const bool deep = sspec.format.size() > 1;  // uint16, half, float sources
  if (staged->width != sw || staged->height != sh || staged->channels != nch ||
      staged->encoding != options.encoding || staged->linear.empty() != !keeps_linear(options, sw, sh))
    return fail(WarpStatus::bad_input, "the staged source is not this source under these options");
  const std::vector<float>& linear = staged->linear;
  const bool keep_linear = !linear.empty();

  // 2. The page's triangles, bucketed by band.
  const int W = int(atlas_width), H = int(atlas_height);
  const int g = int(options.gutter);
  const int band_rows = std::max(1, options.band_rows);
  const int bands = (H + band_rows - 1) / band_rows;
  std::vector<Tri> tris;
  std::vector<std::vector<uint32_t>> band_tris(bands);
  const float* m = options.uv_transform;
  for (uint32_t pi = 0; pi < prims.size(); ++pi) {
    const WarpPrimitive& p = prims[pi];
    const uint32_t nf = uint32_t(p.atlas_uv.size() / 6);
    for (uint32_t f = 0; f < nf; ++f) {
      if (!p.page_of_face.empty() && p.page_of_face[f] != options.page) continue;
      Tri tr{};
      for (int k = 0; k < 3; ++k) {
        const size_t c = 3 * size_t(f) + k;
        tr.x[k] = double(p.atlas_uv[2 * c]) * W;
        tr.y[k] = double(p.atlas_uv[2 * c + 1]) * H;
        const double u = p.source_uv[2 * c], v = p.source_uv[2 * c + 1];
        tr.s[k] = double(m[0]) * u + double(m[1]) * v + double(m[2]);
        tr.t[k] = double(m[3]) * u + double(m[4]) * v + double(m[5]);
      }
      const double e1x = tr.x[1] - tr.x[0], e1y = tr.y[1] - tr.y[0];
      const double e2x = tr.x[2] - tr.x[0], e2y = tr.y[2] - tr.y[0];
      const double det = e1x * e2y - e2x * e1y;
      if (!(std::abs(det) > 1e-12) || !std::isfinite(det)) continue;
      // J = [dS] * inverse([e1 e2]).
      const double i00 = e2y / det, i01 = -e2x / det, i10 = -e1y / det, i11 = e1x / det;
      const double ds1 = tr.s[1] - tr.s[0], ds2 = tr.s[2] - tr.s[0];
      const double dt1 = tr.t[1] - tr.t[0], dt2 = tr.t[2] - tr.t[0];
      tr.dsdx = float(ds1 * i00 + ds2 * i10);
      tr.dsdy = float(ds1 * i01 + ds2 * i11);
      tr.dtdx = float(dt1 * i00 + dt2 * i10);
      tr.dtdy = float(dt1 * i01 + dt2 * i11);
      {
        // Texel-exact: the map in source texels per atlas texel, and where
        // it sends the centre of the texel under corner 0.
        tr.sa = (ds1 * i00 + ds2 * i10) * sw, tr.sb = (ds1 * i01 + ds2 * i11) * sw;
        tr.sc = (dt1 * i00 + dt2 * i10) * sh, tr.sd = (dt1 * i01 + dt2 * i11) * sh;
        tr.sx0 = tr.s[0] * sw, tr.sy0 = tr.t[0] * sh;
        // Draco's quantized positions move each face's map by ~1e-4 from
        // the patch's similarity: the centres under all three corners must
        // land within 1/20 texel of source texel centres.
        tr.exact =
            options.copy_exact_texels && !normal_map && signed_permutation(tr.sa, tr.sb, tr.sc, tr.sd, 1e-3);
        for (int k = 0; k < 3 && tr.exact; ++k) {
          const double cx = std::floor(tr.x[k]) + 0.5 - tr.x[0], cy = std::floor(tr.y[k]) + 0.5 - tr.y[0];
          const double px = tr.sx0 + tr.sa * cx + tr.sb * cy - 0.5,
                       py = tr.sy0 + tr.sc * cx + tr.sd * cy - 0.5;
          tr.exact = std::abs(px - std::round(px)) <= 0.05 && std::abs(py - std::round(py)) <= 0.05;
        }
      }
      {
        // Largest stretch of the atlas -> source texel map (its top singular value).
        const double a = double(tr.dsdx) * sw, b = double(tr.dsdy) * sw;
        const double c = double(tr.dtdx) * sh, d = double(tr.dtdy) * sh;
        const double s1 = a * a + b * b + c * c + d * d, s2 = a * d - b * c;
        const double sigma2 = 0.5 * (s1 + std::sqrt(std::max(0.0, s1 * s1 - 4 * s2 * s2)));
        tr.magnifies = sigma2 <= 1.0;
      }
      tr.prim = pi;
      tr.face = f;
      const double y0 = std::min({tr.y[0], tr.y[1], tr.y[2]}), y1 = std::max({tr.y[0], tr.y[1], tr.y[2]});
      const int r0 = std::max(0, int(std::ceil(y0)) - 1 - g), r1 = std::min(H - 1, int(std::floor(y1)) + g);
      if (r0 > r1) continue;
      const uint32_t id = uint32_t(tris.size());
      tris.push_back(tr);
      for (int b = r0 / band_rows; b <= r1 / band_rows; ++b) band_tris[b].push_back(id);
    }
  }

  // 3. Output and lookups, band by band.
  const TypeDesc out_type = deep ? TypeDesc::UINT16 : TypeDesc::UINT8;
  out.reset(ImageSpec(W, H, nch, out_type));
  const double qmax = deep ? 65535.0 : 255.0;
  std::vector<uint8_t> empty(size_t(W) * H, 0);
  std::vector<uint8_t> kind(size_t(W) * H, 0);  // 1: covered, 2: gutter (filled by dilation)
  // The cache is ours, created and torn down with the texture system: a
  // private cache the system made for itself outlived it, and kept each
  // warp's tiles (about 23 MB per Duck encode in a long-running process).
  OIIO::ImageCache* ic = OIIO::ImageCache::create(false);
  OIIO::TextureSystem* ts = OIIO::TextureSystem::create(false, ic);
  const auto release = [&] {
    OIIO::TextureSystem::destroy(ts);
    OIIO::ImageCache::destroy(ic, true);
  };
  ts->attribute("automip", 1);
  ts->attribute("max_memory_MB", 512.0f);
  const OIIO::ustring tex_name(staged->path);
  {
    OIIO::ImageSpec probe;
    if (!ts->get_imagespec(tex_name, 0, probe)) {
      std::string e = ts->geterror();
      release();
      return fail(WarpStatus::texture_error, "cannot open the staged texture: " + e);
    }
  }
  std::vector<double> sum(nch, 0.0);
  uint64_t covered = 0, gutter = 0, lookups = 0;

  // Per worker: sums merged after the join, and buffers reused band to band.
  struct Scratch {
    std::vector<double> sum;
    uint64_t covered = 0, gutter = 0, lookups = 0;
    std::vector<int32_t> owner, near_col;
    std::vector<float> dist;
    std::vector<uint8_t> row_out;
  };
  const size_t thread_cap = options.threads > 0 ? size_t(options.threads) : 0;  // 0: every core
  const auto wrap_s = to_imagebuf_wrap(options.wrap_s), wrap_t = to_imagebuf_wrap(options.wrap_t);
  std::vector<Scratch> scratch(worker_count(size_t(bands), thread_cap));
  for (Scratch& sc : scratch) sc.sum.assign(nch, 0.0), sc.row_out.resize(size_t(W) * nch * (deep ? 2 : 1));
  run_in_parallel(size_t(bands), scratch.size(), [&](size_t band, size_t worker) {
    Scratch& sc = scratch[worker];
    std::vector<double>& my_sum = sc.sum;
    uint64_t& my_cov = sc.covered;
    uint64_t& my_gut = sc.gutter;
    uint64_t& my_look = sc.lookups;
    std::vector<int32_t>& owner = sc.owner;
    std::vector<int32_t>& near_col = sc.near_col;
    std::vector<float>& dist = sc.dist;
    std::vector<uint8_t>& row_out = sc.row_out;
    OIIO::TextureSystem::Perthread* pt = ts->get_perthread_info();
    OIIO::TextureSystem::TextureHandle* th = ts->get_texture_handle(tex_name, pt);
    const CubicSampler cubic(linear, sw, sh, nch, options.wrap_s, options.wrap_t);
    OIIO::TextureOpt opt;
    opt.swrap = to_oiio(options.wrap_s);
    opt.twrap = to_oiio(options.wrap_t);
    opt.anisotropic = std::max(1, int(options.anisotropy));
    opt.interpmode =
        options.bicubic ? OIIO::TextureOpt::InterpSmartBicubic : OIIO::TextureOpt::InterpBilinear;
    float value[4];
    const int b = int(band);
    const int y0 = b * band_rows, y1 = std::min(H, y0 + band_rows);
    const int e0 = std::max(0, y0 - g), e1 = std::min(H, y1 + g);
    const int erows = e1 - e0;
    owner.assign(size_t(W) * erows, -1);
    dist.assign(size_t(W) * erows, 1e30f);
    // Conservative raster: texels whose square meets a triangle; the
    // nearest triangle (distance from the texel centre) owns the texel.
    for (uint32_t id : band_tris[b]) {
      const Tri& tr = tris[id];
      double px[3] = {tr.x[0], tr.x[1], tr.x[2]}, py[3] = {tr.y[0], tr.y[1], tr.y[2]};
      if ((px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]) < 0)
        std::swap(px[1], px[2]), std::swap(py[1], py[2]);
      const int i0 = std::max(0, int(std::ceil(std::min({px[0], px[1], px[2]}))) - 1);
      const int i1 = std::min(W - 1, int(std::floor(std::max({px[0], px[1], px[2]}))));
      const int j0 = std::max(e0, int(std::ceil(std::min({py[0], py[1], py[2]}))) - 1);
      const int j1 = std::min(e1 - 1, int(std::floor(std::max({py[0], py[1], py[2]}))));
      double ex[3], ey[3], slack[3];
      for (int k = 0; k < 3; ++k) {
        ex[k] = px[(k + 1) % 3] - px[k];
        ey[k] = py[(k + 1) % 3] - py[k];
        slack[k] = 0.5 * (std::abs(ex[k]) + std::abs(ey[k]));
      }
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const double x = i + 0.5, y = j + 0.5;
          bool touch = true, inside = true;
          for (int k = 0; k < 3; ++k) {
            const double e = ex[k] * (y - py[k]) - ey[k] * (x - px[k]);
            if (e + slack[k] < 0) touch = false;
            if (e < 0) inside = false;
          }
          if (!touch) continue;
          float d = 0;
          if (!inside) {
            double bc[3];
            closest_barycentric(tr, x, y, bc);
            const double cx = bc[0] * tr.x[0] + bc[1] * tr.x[1] + bc[2] * tr.x[2];
            const double cy = bc[0] * tr.y[0] + bc[1] * tr.y[1] + bc[2] * tr.y[2];
            d = float((cx - x) * (cx - x) + (cy - y) * (cy - y));
          }
          const size_t at = size_t(j - e0) * W + i;
          if (d < dist[at]) dist[at] = d, owner[at] = int32_t(id);
        }
      }
    }
    // Nearest owned column within g in each row (two scans).
    near_col.assign(size_t(W) * erows, -1);
    for (int r = 0; r < erows; ++r) {
      const int32_t* o = &owner[size_t(r) * W];
      int32_t* nc = &near_col[size_t(r) * W];
      int last = -1000000;
      for (int i = 0; i < W; ++i) {
        if (o[i] >= 0) last = i;
        if (i - last <= g) nc[i] = last;
      }
      last = 1000000;
      for (int i = W - 1; i >= 0; --i) {
        if (o[i] >= 0) last = i;
        if (last - i <= g && (nc[i] < 0 || last - i < i - nc[i])) nc[i] = last;
      }
    }
    for (int y = y0; y < y1; ++y) {
      for (int x = 0; x < W; ++x) {
        // The texel whose sample this texel takes: itself or its nearest owned one.
        int ox = -1, oy = -1;
        if (owner[size_t(y - e0) * W + x] >= 0) {
          ox = x, oy = y;
        } else {
          long best = 1L << 40;
          for (int yy = std::max(e0, y - g); yy < std::min(e1, y + g + 1); ++yy) {
            const int c = near_col[size_t(yy - e0) * W + x];
            if (c < 0) continue;
            const long d = long(yy - y) * (yy - y) + long(c - x) * (c - x);
            if (d < best) best = d, ox = c, oy = yy;
          }
        }
        uint8_t* dst8 = &row_out[size_t(x) * nch * (deep ? 2 : 1)];
        if (ox < 0) {
          empty[size_t(y) * W + x] = 1;
          continue;
        }
        const Tri& tr = tris[owner[size_t(oy - e0) * W + ox]];
        const bool is_cov = ox == x && oy == y;
        // Writes the texel's values (in [0, 1], as the atlas stores them).
        const auto store = [&](const float* v) {
          for (int c = 0; c < nch; ++c) {
            // A NaN (a lookup far outside any sane UV) stores 0, not an undefined cast.
            const double q = v[c] == v[c] ? std::round(std::clamp(double(v[c]), 0.0, 1.0) * qmax) : 0.0;
            if (deep)
              reinterpret_cast<uint16_t*>(dst8)[c] = uint16_t(q);
            else
              dst8[c] = uint8_t(q);
            if (is_cov) my_sum[c] += q;
          }
          kind[size_t(y) * W + x] = is_cov ? 1 : 2;
          ++(is_cov ? my_cov : my_gut);
        };
        if (tr.exact) {
          const double dx = x + 0.5 - tr.x[0], dy = y + 0.5 - tr.y[0];
          const int ix = wrap_texel_index(long(std::floor(tr.sx0 + tr.sa * dx + tr.sb * dy)), sw, wrap_s);
          const int iy = wrap_texel_index(long(std::floor(tr.sy0 + tr.sc * dx + tr.sd * dy)), sh, wrap_t);
          source.getpixel(ix, iy, value, nch);
          ++my_look;
          store(value);  // the source's own encoded values
          continue;
        }
        double bc[3];
        closest_barycentric(tr, ox + 0.5, oy + 0.5, bc);
        const float s = float(bc[0] * tr.s[0] + bc[1] * tr.s[1] + bc[2] * tr.s[2]);
        const float t = float(bc[0] * tr.t[0] + bc[1] * tr.t[1] + bc[2] * tr.t[2]);
        value[0] = value[1] = value[2] = 0, value[3] = 1;
        if (keep_linear && tr.magnifies)
          cubic.sample(s, t, value);
        else
          ts->texture(th, pt, opt, s, t, tr.dsdx, tr.dtdx, tr.dsdy, tr.dtdy, nch, value);
        ++my_look;
        if (normal_map) {
          const WarpPrimitive& p = prims[tr.prim];
          Vec3 To, Bo, No, Tn, Bn, Nn;
          frame_at(p, p.old_tangents, tr.face, bc, To, Bo, No);
          frame_at(p, p.new_tangents, tr.face, bc, Tn, Bn, Nn);
          const Vec3 n{2.0 * value[0] - 1, 2.0 * value[1] - 1, 2.0 * value[2] - 1};
          const Vec3 obj = n.x * To + n.y * Bo + n.z * No;
          const Vec3 nn = solve_frame(Tn, Bn, Nn, obj);
          value[0] = float(nn.x * 0.5 + 0.5);
          value[1] = float(nn.y * 0.5 + 0.5);
          value[2] = float(nn.z * 0.5 + 0.5);
        }
        for (int c = 0; c < nch; ++c)
          if (srgb && is_color_channel(c, nch)) value[c] = linear_to_srgb(std::max(value[c], 0.0f));
        store(value);
      }
      // Empty texels get written later (EmptyFill); copy the row now.
      uint8_t* base = static_cast<uint8_t*>(out.localpixels());
      const size_t row_bytes = size_t(W) * nch * (deep ? 2 : 1);
      std::copy(row_out.begin(), row_out.end(), base + size_t(y) * row_bytes);
    }
  });
  for (const Scratch& sc : scratch) {
    for (int c = 0; c < nch; ++c) sum[c] += sc.sum[c];
    covered += sc.covered, gutter += sc.gutter, lookups += sc.lookups;
  }
  release();

  // 3b. Least-squares texels, then the gutter again from them.
  if (options.least_squares && keep_linear && !normal_map) {
    const auto f0 = std::chrono::steady_clock::now();
    FitInput in{tris, prims, linear, sw, sh, nch, W, H, srgb, deep, options};
    fit_atlas(in, static_cast<uint8_t*>(out.localpixels()), kind, thread_cap, report.fit);
    report.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count();
  }

  // 4. Everything else, by EmptyFill: the mean covered colour, the nearest
  // kept texel (PNG), or a pull-push fill (JPEG).
  uint8_t* base = static_cast<uint8_t*>(out.localpixels());
  const size_t texel_bytes = size_t(nch) * (deep ? 2 : 1);
  uint8_t fill[8] = {};
  for (int c = 0; c < nch; ++c) {
    const double q = covered ? std::round(sum[c] / double(covered)) : 0.0;
    if (deep)
      reinterpret_cast<uint16_t*>(fill)[c] = uint16_t(q);
    else
      fill[c] = uint8_t(q);
  }
  uint64_t n_empty = 0;
  for (size_t i = 0; i < empty.size(); ++i)
    if (empty[i]) {
      if (options.empty_fill == EmptyFill::mean) std::copy(fill, fill + texel_bytes, base + i * texel_bytes);
      ++n_empty;
    }
  if (options.empty_fill == EmptyFill::nearest) {
    // Distances are from the kept texels, the gutter's outer ring among them.
    const double beyond_gutter = std::max(1.0, double(options.nearest_reach) - double(options.gutter));
    nearest_fill(base, W, H, nch, deep, empty, beyond_gutter);
  }
  if (options.empty_fill == EmptyFill::pull_push) {
    pull_push_fill(base, W, H, nch, deep, empty);
    for (const int block : {16, 8}) flatten_empty_blocks(base, W, H, nch, deep, empty, block);
  }
  report.covered_texels = covered;
  report.gutter_texels = gutter;
  report.empty_texels = n_empty;
  report.lookups = lookups;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report.texels_per_second = report.seconds > 0 ? double(covered + gutter) / report.seconds : 0;
  if (report_out) *report_out = report;
  return WarpStatus::ok;
}

}  // namespace gltfwarp
