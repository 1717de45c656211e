// A small software rasteriser for the rendered-view PSNR of the benchmark
// (issue 16): the cross-check of compare's surface PSNR with what a viewer
// shows.
//
// Both models (source and decoded) are drawn from the same fixed views:
// orthographic, the whole model in view (the source's bounding sphere fills
// the image), unlit, base colour texture only (through TEXCOORD_0, with the
// slot's KHR_texture_transform and the sampler's wrap modes), no culling,
// depth-tested. Textures are sampled as GPUs do with LINEAR_MIPMAP_LINEAR:
// a mip pyramid made by 2x2 box filtering in linear light, the level of
// detail from the triangle's texel footprint per pixel (log2 of the longer of
// the two screen-axis derivatives, OpenGL 4.6 §8.14.1), bilinear within and
// linear between levels, texel centres at (i + 0.5) / W. Under an
// orthographic camera a triangle's UVs are affine in screen space, so its
// derivatives are constant over it.
//
// The PSNR is over the pixels both renders cover (foreground), RGB encoded
// to sRGB 0..255 as a display shows it. Besides the PSNR it reports where
// the error sits: per mip level the decoded side sampled (0, 1, 2, 3+), and
// the share of the squared error carried by the worst 1% of pixels.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include <tiny_gltf.h>

#include "codec/encode/texture/texel_reach.h"
#include "codec/encode/texture/texture_sampler.h"
#include "format/gltf/gltf_materials.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp::bench {

using Mat4 = std::array<double, 16>;  // column-major, as glTF

inline Mat4 mat_mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int rr = 0; rr < 4; ++rr) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
      r[c * 4 + rr] = s;
    }
  return r;
}

inline Mat4 node_local(const tinygltf::Node& n) {
  Mat4 m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (n.matrix.size() == 16) {
    std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
    return m;
  }
  const double t[3] = {n.translation.size() == 3 ? n.translation[0] : 0,
                       n.translation.size() == 3 ? n.translation[1] : 0,
                       n.translation.size() == 3 ? n.translation[2] : 0};
  double q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
  if (n.rotation.size() == 4) std::copy(n.rotation.begin(), n.rotation.end(), q);
  if (n.scale.size() == 3) std::copy(n.scale.begin(), n.scale.end(), s);
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  const double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                       2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                       2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m[c * 4 + r] = R[c * 3 + r] * s[c];
  m[12] = t[0], m[13] = t[1], m[14] = t[2];
  return m;
}

// Every (mesh, world matrix) the default scene (or every root) instantiates;
// skinned nodes draw their mesh in its bind pose (identity).
inline std::vector<std::pair<int, Mat4>> mesh_instances(const tinygltf::Model& m) {
  std::vector<std::pair<int, Mat4>> out;
  const Mat4 id{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::function<void(int, const Mat4&, int)> walk = [&](int n, const Mat4& parent, int depth) {
    if (n < 0 || n >= int(m.nodes.size()) || depth > 64) return;
    const tinygltf::Node& node = m.nodes[n];
    const Mat4 world = mat_mul(parent, node_local(node));
    if (node.mesh >= 0 && node.mesh < int(m.meshes.size()))
      out.push_back({node.mesh, node.skin >= 0 ? id : world});
    for (int c : node.children) walk(c, world, depth + 1);
  };
  std::vector<int> roots;
  if (!m.scenes.empty()) roots = m.scenes[std::clamp(m.defaultScene, 0, int(m.scenes.size()) - 1)].nodes;
  for (int r : roots) walk(r, id, 0);
  if (out.empty())
    for (size_t i = 0; i < m.meshes.size(); ++i) out.push_back({int(i), id});
  return out;
}

// A texture as a mip pyramid of linear RGB floats.
struct MipTexture {
  struct Level {
    int w = 0, h = 0;
    std::vector<float> rgb;
  };
  std::vector<Level> levels;
  OIIO::ImageBuf::WrapMode wrap_s = OIIO::ImageBuf::WrapPeriodic, wrap_t = OIIO::ImageBuf::WrapPeriodic;
  bool srgb = false;

  explicit MipTexture(const TextureSampler& t) : wrap_s(t.wrap_s), wrap_t(t.wrap_t), srgb(t.srgb) {
    const int w = t.pixels.spec().width, h = t.pixels.spec().height, nc = t.pixels.nchannels();
    std::vector<float> all(size_t(w) * h * nc);
    t.pixels.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, nc), OIIO::TypeDesc::FLOAT, all.data());
    Level l0{w, h, std::vector<float>(size_t(w) * h * 3)};
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (int c = 0; c < 3; ++c) l0.rgb[3 * i + c] = all[i * nc + (nc < 3 ? 0 : c)];
    levels.push_back(std::move(l0));
    while (levels.back().w > 1 || levels.back().h > 1) {
      const Level& a = levels.back();
      Level b{std::max(1, a.w / 2), std::max(1, a.h / 2), {}};
      b.rgb.resize(size_t(b.w) * b.h * 3);
      for (int y = 0; y < b.h; ++y)
        for (int x = 0; x < b.w; ++x)
          for (int c = 0; c < 3; ++c) {
            double s = 0;
            int n = 0;
            for (int dy = 0; dy < 2; ++dy)
              for (int dx = 0; dx < 2; ++dx) {
                const int sx = std::min(2 * x + dx, a.w - 1), sy = std::min(2 * y + dy, a.h - 1);
                s += a.rgb[(size_t(sy) * a.w + sx) * 3 + c];
                ++n;
              }
            b.rgb[(size_t(y) * b.w + x) * 3 + c] = float(s / n);
          }
      levels.push_back(std::move(b));
    }
  }

  static int wrap(int i, int n, OIIO::ImageBuf::WrapMode m) {
    if (m == OIIO::ImageBuf::WrapClamp || m == OIIO::ImageBuf::WrapBlack) return std::clamp(i, 0, n - 1);
    if (m == OIIO::ImageBuf::WrapMirror) {
      const int p = ((i % (2 * n)) + 2 * n) % (2 * n);
      return p < n ? p : 2 * n - 1 - p;
    }
    return ((i % n) + n) % n;
  }

  void bilinear(int level, double u, double v, double out[3]) const {
    const Level& l = levels[size_t(level)];
    const double x = u * l.w - 0.5, y = v * l.h - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int x0 = wrap(int(fx), l.w, wrap_s), x1 = wrap(int(fx) + 1, l.w, wrap_s);
    const int y0 = wrap(int(fy), l.h, wrap_t), y1 = wrap(int(fy) + 1, l.h, wrap_t);
    for (int c = 0; c < 3; ++c) {
      auto at = [&](int xx, int yy) { return double(l.rgb[(size_t(yy) * l.w + xx) * 3 + c]); };
      out[c] = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) +
               ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
    }
  }

  // LINEAR_MIPMAP_LINEAR at level of detail `lod` (>= 0).
  void trilinear(double u, double v, double lod, double out[3]) const {
    const double top = double(levels.size() - 1);
    lod = std::clamp(lod, 0.0, top);
    const int l0 = int(std::floor(lod));
    const double f = lod - l0;
    bilinear(l0, u, v, out);
    if (f > 0 && l0 + 1 <= int(top)) {
      double b[3];
      bilinear(l0 + 1, u, v, b);
      for (int c = 0; c < 3; ++c) out[c] = (1 - f) * out[c] + f * b[c];
    }
  }
};

struct View {
  std::array<double, 3> dir;  // towards the viewer, normalised by the caller
};

inline std::vector<View> default_views() {
  std::vector<View> v = {{{0, 0, 1}},  {{0, 0, -1}},      {{1, 0, 0}},
                         {{-1, 0, 0}}, {{0.6, 0.7, 0.4}}, {{-0.5, -0.6, -0.6}}};
  for (auto& x : v) {
    const double n = std::sqrt(x.dir[0] * x.dir[0] + x.dir[1] * x.dir[1] + x.dir[2] * x.dir[2]);
    for (double& c : x.dir) c /= n;
  }
  return v;
}

// One render: linear RGB and the level of detail sampled per pixel (-1: background).
struct Frame {
  int size = 0;
  std::vector<float> rgb, lod, depth;
};

struct Camera {
  double right[3], up[3], dir[3], centre[3], scale;  // pixels per model unit
};

// The draw list of a model: base colour textures sampled through TEXCOORD_0.
class Scene {
 public:
  // fill_unreached: the reference's textures get their unused texels
  // filled from the charts first (texel_reach.h), so the source's own chart
  // bleed at minified levels is not counted against either encoding.
  explicit Scene(const tinygltf::Model& m, bool fill_unreached = false) {
    for (const auto& [mesh, world] : mesh_instances(m))
      for (const auto& p : m.meshes[size_t(mesh)].primitives) {
        if (!is_triangle_mode(p.mode) || p.material < 0) continue;
        const auto slots = texture_slots(m, p.material);
        const TextureSlot* base = nullptr;
        for (const auto& s : slots)
          if (s.extension.empty() && s.key == "baseColorTexture" && s.tex_coord == 0) base = &s;
        if (!base) continue;
        const TextureSampler* tex = texture(m, *base);
        if (!tex) continue;
        PrimitiveGeometry g;
        if (!read_primitive(m, p, g).empty()) continue;
        const VertexAttribute *pos = g.find("POSITION"), *uv = g.find("TEXCOORD_0");
        if (!pos || !uv) continue;
        Draw d;
        d.texture = base->texture;
        d.transform = base->transform;
        const std::vector<float> pf = pos->to_floats(), uf = uv->to_floats();
        d.pos.resize(pf.size());
        for (size_t v = 0; v < pf.size() / 3; ++v)
          for (int r = 0; r < 3; ++r)
            d.pos[3 * v + r] = world[r] * pf[3 * v] + world[4 + r] * pf[3 * v + 1] +
                               world[8 + r] * pf[3 * v + 2] + world[12 + r];
        d.uv.assign(uf.begin(), uf.end());
        d.tris = g.triangles;
        draws_.push_back(std::move(d));
      }
    for (auto& [index, sampler] : samplers_) {
      if (!sampler) continue;
      if (fill_unreached) {
        TexelReach reach(*sampler);
        for (const Draw& d : draws_)
          if (d.texture == index) {
            std::vector<float> faces;
            faces.reserve(d.tris.size() * 2);
            for (uint32_t v : d.tris)
              if (2 * size_t(v) + 1 < d.uv.size()) faces.insert(faces.end(), {d.uv[2 * v], d.uv[2 * v + 1]});
            if (faces.size() == d.tris.size() * 2) reach.add_triangles(faces, d.transform);
          }
        reach.fill_unreached(*sampler);
      }
      textures_[index] = std::make_unique<MipTexture>(*sampler);
    }
    for (Draw& d : draws_) d.tex = textures_[d.texture].get();
    samplers_.clear();  // the pyramids hold the texels now
  }

  bool empty() const { return draws_.empty(); }

  // A camera looking along -view.dir with the scene's bounding sphere filling `size` pixels.
  Camera camera(const View& view, int size) const {
    Camera c{};
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const auto& d : draws_)
      for (size_t i = 0; i < d.pos.size(); ++i)
        lo[i % 3] = std::min(lo[i % 3], d.pos[i]), hi[i % 3] = std::max(hi[i % 3], d.pos[i]);
    double r = 0;
    for (int i = 0; i < 3; ++i)
      c.centre[i] = 0.5 * (lo[i] + hi[i]), r += 0.25 * (hi[i] - lo[i]) * (hi[i] - lo[i]);
    r = std::max(std::sqrt(r), 1e-12);
    for (int i = 0; i < 3; ++i) c.dir[i] = view.dir[i];
    const double up0[3] = {std::abs(view.dir[1]) > 0.9 ? 1.0 : 0.0, std::abs(view.dir[1]) > 0.9 ? 0.0 : 1.0,
                           0};
    // right = up0 x dir, up = dir x right
    c.right[0] = up0[1] * c.dir[2] - up0[2] * c.dir[1];
    c.right[1] = up0[2] * c.dir[0] - up0[0] * c.dir[2];
    c.right[2] = up0[0] * c.dir[1] - up0[1] * c.dir[0];
    const double rn = std::sqrt(c.right[0] * c.right[0] + c.right[1] * c.right[1] + c.right[2] * c.right[2]);
    for (double& x : c.right) x /= rn;
    c.up[0] = c.dir[1] * c.right[2] - c.dir[2] * c.right[1];
    c.up[1] = c.dir[2] * c.right[0] - c.dir[0] * c.right[2];
    c.up[2] = c.dir[0] * c.right[1] - c.dir[1] * c.right[0];
    c.scale = size / (2.05 * r);
    return c;
  }

  Frame render(const Camera& cam, int size) const {
    Frame f;
    f.size = size;
    const size_t n = size_t(size) * size;
    f.rgb.assign(3 * n, 0.0f);
    f.lod.assign(n, -1.0f);
    f.depth.assign(n, 1e30f);
    for (const auto& d : draws_) {
      const size_t nv = d.pos.size() / 3;
      std::vector<double> sx(nv), sy(nv), sz(nv);
      for (size_t v = 0; v < nv; ++v) {
        double p[3];
        for (int i = 0; i < 3; ++i) p[i] = d.pos[3 * v + i] - cam.centre[i];
        sx[v] = size * 0.5 + cam.scale * (p[0] * cam.right[0] + p[1] * cam.right[1] + p[2] * cam.right[2]);
        sy[v] = size * 0.5 - cam.scale * (p[0] * cam.up[0] + p[1] * cam.up[1] + p[2] * cam.up[2]);
        sz[v] = -(p[0] * cam.dir[0] + p[1] * cam.dir[1] + p[2] * cam.dir[2]);  // smaller is nearer
      }
      const auto& T = d.transform;
      const int W = d.tex->levels[0].w, H = d.tex->levels[0].h;
      for (size_t t = 0; t + 2 < d.tris.size(); t += 3) {
        const uint32_t a = d.tris[t], b = d.tris[t + 1], c = d.tris[t + 2];
        if (a >= nv || b >= nv || c >= nv) continue;
        const double area = (sx[b] - sx[a]) * (sy[c] - sy[a]) - (sx[c] - sx[a]) * (sy[b] - sy[a]);
        if (std::abs(area) < 1e-12) continue;
        // Texture coordinates after the slot transform, and their screen derivatives.
        double u[3], v[3];
        const uint32_t id[3] = {a, b, c};
        for (int k = 0; k < 3; ++k) {
          const double uu = d.uv[2 * id[k]], vv = d.uv[2 * id[k] + 1];
          u[k] = T[0] * uu + T[1] * vv + T[2];
          v[k] = T[3] * uu + T[4] * vv + T[5];
        }
        const double dudx = ((u[1] - u[0]) * (sy[c] - sy[a]) - (u[2] - u[0]) * (sy[b] - sy[a])) / area;
        const double dudy = ((u[2] - u[0]) * (sx[b] - sx[a]) - (u[1] - u[0]) * (sx[c] - sx[a])) / area;
        const double dvdx = ((v[1] - v[0]) * (sy[c] - sy[a]) - (v[2] - v[0]) * (sy[b] - sy[a])) / area;
        const double dvdy = ((v[2] - v[0]) * (sx[b] - sx[a]) - (v[1] - v[0]) * (sx[c] - sx[a])) / area;
        const double rho = std::max(std::hypot(dudx * W, dvdx * H), std::hypot(dudy * W, dvdy * H));
        const double lod = rho > 0 ? std::max(0.0, std::log2(rho)) : 0.0;
        const int x0 = std::max(0, int(std::floor(std::min({sx[a], sx[b], sx[c]})))),
                  x1 = std::min(size - 1, int(std::ceil(std::max({sx[a], sx[b], sx[c]}))));
        const int y0 = std::max(0, int(std::floor(std::min({sy[a], sy[b], sy[c]})))),
                  y1 = std::min(size - 1, int(std::ceil(std::max({sy[a], sy[b], sy[c]}))));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const double px = x + 0.5, py = y + 0.5;
            const double w1 = ((px - sx[a]) * (sy[c] - sy[a]) - (sx[c] - sx[a]) * (py - sy[a])) / area;
            const double w2 = ((sx[b] - sx[a]) * (py - sy[a]) - (px - sx[a]) * (sy[b] - sy[a])) / area;
            const double w0 = 1 - w1 - w2;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            const double z = w0 * sz[a] + w1 * sz[b] + w2 * sz[c];
            const size_t i = size_t(y) * size + x;
            if (z >= f.depth[i]) continue;
            f.depth[i] = float(z);
            double rgb[3];
            d.tex->trilinear(w0 * u[0] + w1 * u[1] + w2 * u[2], w0 * v[0] + w1 * v[1] + w2 * v[2], lod, rgb);
            for (int k = 0; k < 3; ++k) f.rgb[3 * i + k] = float(rgb[k]);
            f.lod[i] = float(lod);
          }
      }
    }
    return f;
  }

 private:
  struct Draw {
    int texture = -1;
    const MipTexture* tex = nullptr;
    std::array<double, 6> transform{};
    std::vector<double> pos;
    std::vector<float> uv;
    std::vector<uint32_t> tris;
  };
  const TextureSampler* texture(const tinygltf::Model& m, const TextureSlot& s) {
    auto it = samplers_.find(s.texture);
    if (it != samplers_.end()) return it->second.get();
    // The image's bytes: its own, or its bufferView's (a decoded model holds them there).
    std::unique_ptr<TextureSampler> loaded;
    if (const int im = texture_image(m, s.texture); im >= 0) {
      const tinygltf::Image& image = m.images[size_t(im)];
      std::vector<uint8_t> bytes = image.image;
      if (bytes.empty() && image.bufferView >= 0) {
        const auto& bv = m.bufferViews[size_t(image.bufferView)];
        const auto& buf = m.buffers[size_t(bv.buffer)].data;
        bytes.assign(buf.begin() + long(bv.byteOffset), buf.begin() + long(bv.byteOffset + bv.byteLength));
      }
      int wrap_s = 0, wrap_t = 0;
      texture_wraps(m, s.texture, wrap_s, wrap_t);
      auto t = std::make_unique<TextureSampler>();  // the slot's transform is applied per vertex, in render()
      if (load_texture_sampler(bytes, s.color_space == ColorSpace::srgb, wrap_s, wrap_t, {1, 0, 0, 0, 1, 0},
                               *t)
              .empty() &&
          t->ok)
        loaded = std::move(t);
    }
    return (samplers_[s.texture] = std::move(loaded)).get();
  }
  std::map<int, std::unique_ptr<TextureSampler>> samplers_;
  std::map<int, std::unique_ptr<MipTexture>> textures_;
  std::vector<Draw> draws_;
};

inline double to_srgb8(double linear) {
  linear = std::clamp(linear, 0.0, 1.0);
  const double s = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return 255.0 * s;
}

struct RenderComparison {
  double sse = 0;
  size_t pixels = 0;                   // foreground pixels compared (both renders cover them)
  std::array<double, 4> sse_by_lod{};  // decoded side's mip level 0, 1, 2, 3+
  std::array<size_t, 4> pixels_by_lod{};
  std::vector<double> pixel_errors;  // per pixel squared error (sum over RGB), for the worst share
  double psnr() const { return psnr_of(sse, pixels); }
  static double psnr_of(double sse, size_t n) {
    if (!n) return 0;
    const double mse = sse / (3.0 * double(n));
    return mse <= 0 ? 99.0 : std::min(99.0, 10 * std::log10(255.0 * 255.0 / mse));
  }
  // Share of the squared error carried by the worst `fraction` of the pixels.
  double worst_share(double fraction) const {
    if (pixel_errors.empty() || sse <= 0) return 0;
    std::vector<double> e = pixel_errors;
    const size_t k = std::max<size_t>(1, size_t(fraction * double(e.size())));
    std::nth_element(e.begin(), e.begin() + long(k), e.end(), std::greater<double>());
    double s = 0;
    for (size_t i = 0; i < k; ++i) s += e[i];
    return s / sse;
  }
};

// A frame as a display shows it: sRGB 8-bit RGB, background black.
inline std::vector<uint8_t> frame_srgb8(const Frame& f) {
  std::vector<uint8_t> px(f.rgb.size());
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(std::lround(to_srgb8(f.rgb[i])));
  return px;
}

// Called with each view's index and both frames (to look at a render: compare --save-renders).
using FrameSink = std::function<void(size_t view, const Frame& source, const Frame& decoded)>;

// Renders `source` and `decoded` from every default view at `size` pixels,
// with the cameras of the source, and compares the foreground.
inline RenderComparison compare_renders(const Scene& source, const Scene& decoded, int size,
                                        const FrameSink& sink = {}) {
  RenderComparison r;
  if (source.empty() || decoded.empty()) return r;
  const std::vector<View> views = default_views();
  for (size_t view = 0; view < views.size(); ++view) {
    const Camera cam = source.camera(views[view], size);
    const Frame a = source.render(cam, size), b = decoded.render(cam, size);
    if (sink) sink(view, a, b);
    for (size_t i = 0; i < a.lod.size(); ++i) {
      if (a.lod[i] < 0 || b.lod[i] < 0) continue;
      double e = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = to_srgb8(a.rgb[3 * i + c]) - to_srgb8(b.rgb[3 * i + c]);
        e += d * d;
      }
      const int bucket = std::min(3, int(b.lod[i]));
      r.sse += e;
      r.pixels++;
      r.sse_by_lod[size_t(bucket)] += e;
      r.pixels_by_lod[size_t(bucket)]++;
      r.pixel_errors.push_back(e);
    }
  }
  return r;
}

}  // namespace gltfwarp::bench
