// gltf-warp-compare: the in-process half of scripts/bench (issue 6).
//
// For one glTF model it measures, with the codec's own library and the same
// Draco library every KHR_draco_mesh_compression tool links:
//   - what TEXCOORD_0 costs in Draco at 10/12/14 bits: Draco bytes of the
//     primitive with every attribute it has (TANGENT excepted) minus Draco
//     bytes of the same primitive without TEXCOORD_0, both welded
//     (weld_vertices), so the side without UVs merges the vertices that only
//     UV seams kept apart;
//   - what TANGENT costs in Draco at the default 12/10/14 bits;
//   - our encode (default options and a few texture settings), its file
//     bytes, bitstream bytes, atlas report, encode and decode times;
//   - the Draco-12 explicit-UV file with the original images (the baseline
//     a user would otherwise ship), and the same with images re-encoded as
//     JPEG at the qualities the plot uses;
//   - texture-space PSNR of each decoded file against the source (below);
//   - decode time of ours against decode of the Draco-12 explicit-UV file,
//     both through decode_model in this process, median of --runs runs.
// It also writes the files scripts/bench hands to gltfpack: the textured
// primitives with and without TEXCOORD_0 (TANGENT dropped from both, images
// replaced by one 1x1 PNG so only geometry differs), and a .drc of the first
// explicit-UV Draco primitive for draco_decoder.
//
// Texture-space PSNR: every decoded face is traced back to its source face
// (codec/core/corner_match, by position); on each face, points at the centroids
// of an n x n barycentric subdivision (n grows with the face's source texel
// area, about one point per source texel, 2 <= n <= 64) sample the source
// texture at the source UV (with its KHR_texture_transform and sampler wrap)
// and the decoded texture at the decoded UV, bilinearly. The RGB error over
// all points of all textured slots (normal maps excepted: they are
// re-expressed in the new tangent frame, so their texels legitimately
// change) gives PSNR = 10 log10(255^2 / MSE) on the stored 8-bit values.
//
// Output: one JSON object on stdout. Errors: a line on stderr, exit 1.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "codec/core/corner_match.h"
#include "codec/decode/decoder.h"
#include "codec/encode/encoder.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/texture_sampler.h"
#include "format/bitstream/uvmap_codec.h"
#include "format/gltf/draco_geometry.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_materials.h"
#include "format/gltf/gltf_primitive.h"

using namespace gltfwarp;
using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "gltf-warp-compare: %s\n", what.c_str());
  std::exit(1);
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

size_t file_size(const std::string& p) { return static_cast<size_t>(fs::file_size(p)); }

// ---------------------------------------------------------------- Draco costs

size_t draco_bytes(const std::vector<VertexAttribute>& attrs, const std::vector<uint32_t>& tris,
                   const DracoOptions& o) {
  const DracoEncoded e = draco_encode(attrs, tris, o);
  if (!e.error.empty()) fail("draco_encode: " + e.error);
  return e.bytes.size();
}

std::vector<VertexAttribute> without(const std::vector<VertexAttribute>& attrs,
                                     const std::set<std::string>& drop) {
  std::vector<VertexAttribute> out;
  for (const auto& a : attrs)
    if (!drop.count(a.semantic)) out.push_back(a);
  return out;
}

// ---------------------------------------------------------------- sampling

// A slot's texture as a viewer samples it (codec/encode/texture/texture_sampler.h), as RGB
// on the 0..255 scale; grey images give their one channel three times.
void sample(const TextureSampler& t, double u, double v, float out[3]) {
  float px[4] = {0, 0, 0, 0};
  t.sample(u, v, px);
  const bool grey = t.channels() < 3;
  for (int c = 0; c < 3; ++c) out[c] = 255.0f * px[grey ? 0 : c];
}

struct TextureCache {
  const tinygltf::Model* model;
  std::map<std::pair<int, bool>, TextureSampler> by_texture;
  const TextureSampler* get(int texture, bool srgb) {
    auto it = by_texture.find({texture, srgb});
    if (it != by_texture.end()) return it->second.ok ? &it->second : nullptr;
    TextureSampler& t = by_texture[{texture, srgb}];
    const int img = texture_image(*model, texture);
    if (img < 0) return nullptr;
    const tinygltf::Image& image = model->images[img];
    std::vector<uint8_t> bytes = image.image;
    if (bytes.empty() && image.bufferView >= 0) {
      const auto& bv = model->bufferViews[image.bufferView];
      const auto& buf = model->buffers[bv.buffer].data;
      bytes.assign(buf.begin() + bv.byteOffset, buf.begin() + bv.byteOffset + bv.byteLength);
    }
    int wrap_s = TINYGLTF_TEXTURE_WRAP_REPEAT, wrap_t = TINYGLTF_TEXTURE_WRAP_REPEAT;
    if (const int s = model->textures[texture].sampler; s >= 0) {
      wrap_s = model->samplers[s].wrapS;
      wrap_t = model->samplers[s].wrapT;
    }
    // The slot's transform is applied by the caller.
    if (!load_texture_sampler(bytes, srgb, wrap_s, wrap_t, {1, 0, 0, 0, 1, 0}, t).empty()) return nullptr;
    return t.ok ? &t : nullptr;
  }
};

struct Psnr {
  double sse = 0;
  size_t samples = 0;  // colour samples (3 values each)
  size_t faces_skipped = 0;
  double value() const {
    if (!samples) return 0;
    const double mse = sse / (3.0 * static_cast<double>(samples));
    return mse <= 0 ? 99.0 : std::min(99.0, 10 * std::log10(255.0 * 255.0 / mse));
  }
};

std::vector<float> as_floats(const VertexAttribute& a) {
  std::vector<float> v(a.count() * a.components);
  for (size_t e = 0; e < a.count(); ++e)
    for (int i = 0; i < a.components; ++i) v[e * a.components + i] = a.get(e, i);
  return v;
}

// Texture-space PSNR of `decoded` (plain accessors, TEXCOORD_0 present)
// against `source`, over the primitives listed in `prims`.
Psnr texture_psnr(const tinygltf::Model& source, const tinygltf::Model& decoded,
                  const std::vector<std::pair<int, int>>& prims, int position_bits) {
  Psnr r;
  TextureCache sc{&source, {}}, dc{&decoded, {}};
  for (auto [mi, pi] : prims) {
    const auto& sp = source.meshes[mi].primitives[pi];
    const auto& dp = decoded.meshes[mi].primitives[pi];
    PrimitiveGeometry sg, dg;
    if (!read_primitive(source, sp, sg).empty() || !read_primitive(decoded, dp, dg).empty())
      fail("read_primitive");
    const VertexAttribute *spos = sg.find("POSITION"), *dpos = dg.find("POSITION");
    const VertexAttribute *suv_a = sg.find("TEXCOORD_0"), *duv_a = dg.find("TEXCOORD_0");
    if (!spos || !dpos || !suv_a || !duv_a) fail("psnr: primitive lacks POSITION or TEXCOORD_0");
    const std::vector<float> sposf = as_floats(*spos), dposf = as_floats(*dpos);
    const std::vector<float> suv = as_floats(*suv_a), duv = as_floats(*duv_a);
    // Tolerance: a Draco position quantization step of the source's extent.
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (size_t i = 0; i < sposf.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], sposf[i]);
      hi[i % 3] = std::max(hi[i % 3], sposf[i]);
    }
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-20f});
    const double tol = 1.01 * extent / double((1u << position_bits) - 1);
    const CornerMatch cm = match_corners(sposf, sg.triangles, dposf, dg.triangles, tol);
    // Slot pairs, by slot name; normal maps excepted (see the file comment).
    std::vector<std::pair<const TextureSampler*, const TextureSampler*>> slots;
    std::vector<std::array<double, 6>> xforms_s, xforms_d;
    const auto ss = texture_slots(source, sp.material), ds = texture_slots(decoded, dp.material);
    for (const auto& s : ss) {
      if (s.normal_map || s.tex_coord != 0) continue;
      for (const auto& d : ds) {
        if (d.name() != s.name()) continue;
        const bool srgb = s.color_space == ColorSpace::srgb;
        const TextureSampler *a = sc.get(s.texture, srgb), *b = dc.get(d.texture, srgb);
        if (a && b) {
          slots.push_back({a, b});
          xforms_s.push_back(s.transform);
          xforms_d.push_back(d.transform);
        }
      }
    }
    if (slots.empty()) continue;
    const TextureSampler* ref = slots[0].first;
    const int ref_w = ref->pixels.spec().width, ref_h = ref->pixels.spec().height;
    const char* debug = std::getenv("GLTFWARP_COMPARE_DEBUG");
    std::vector<float> debug_img(debug ? size_t(ref_w) * ref_h * 3 : 0);
    auto repeat = [](int i, int n) { return ((i % n) + n) % n; };
    const size_t nf = dg.triangles.size() / 3;
    for (size_t f = 0; f < nf; ++f) {
      double su[3][2], du[3][2];
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        const uint32_t sc_ = cm.source_corner[3 * f + k];
        const uint32_t sv = sg.triangles[sc_], dv = dg.triangles[3 * f + k];
        double d2 = 0;
        for (int i = 0; i < 3; ++i) d2 += std::pow(double(sposf[3 * sv + i]) - dposf[3 * dv + i], 2);
        if (std::sqrt(d2) > 2 * tol) ok = false;
        su[k][0] = suv[2 * sv];
        su[k][1] = suv[2 * sv + 1];
        du[k][0] = duv[2 * dv];
        du[k][1] = duv[2 * dv + 1];
      }
      if (!ok) {
        r.faces_skipped++;
        continue;
      }
      const double area = 0.5 *
                          std::abs((su[1][0] - su[0][0]) * (su[2][1] - su[0][1]) -
                                   (su[2][0] - su[0][0]) * (su[1][1] - su[0][1])) *
                          ref_w * ref_h;
      const int n = std::clamp(int(std::ceil(std::sqrt(area))), 2, 64);
      auto visit = [&](double b1, double b2) {
        const double b0 = 1 - b1 - b2;
        const double u0 = b0 * su[0][0] + b1 * su[1][0] + b2 * su[2][0];
        const double v0 = b0 * su[0][1] + b1 * su[1][1] + b2 * su[2][1];
        const double u1 = b0 * du[0][0] + b1 * du[1][0] + b2 * du[2][0];
        const double v1 = b0 * du[0][1] + b1 * du[1][1] + b2 * du[2][1];
        for (size_t s = 0; s < slots.size(); ++s) {
          const auto& A = xforms_s[s];
          const auto& B = xforms_d[s];
          float ca[3], cb[3];
          sample(*slots[s].first, A[0] * u0 + A[1] * v0 + A[2], A[3] * u0 + A[4] * v0 + A[5], ca);
          sample(*slots[s].second, B[0] * u1 + B[1] * v1 + B[2], B[3] * u1 + B[4] * v1 + B[5], cb);
          for (int c = 0; c < 3; ++c) r.sse += double(ca[c] - cb[c]) * (ca[c] - cb[c]);
          r.samples++;
          if (debug && s == 0) {
            const int x = repeat(int(std::floor(u0 * ref_w)), ref_w);
            const int y = repeat(int(std::floor(v0 * ref_h)), ref_h);
            for (int c = 0; c < 3; ++c) debug_img[(size_t(y) * ref_w + x) * 3 + c] = cb[c] / 255.0f;
          }
        }
      };
      for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j) {
          visit((i + 1.0 / 3) / n, (j + 1.0 / 3) / n);
          if (i + j < n - 1) visit((i + 2.0 / 3) / n, (j + 2.0 / 3) / n);
        }
    }
    if (debug) {  // the decoded colours painted at the source UVs: compare by eye with the source texture
      OIIO::ImageBuf img(OIIO::ImageSpec(ref_w, ref_h, 3, OIIO::TypeDesc::FLOAT), debug_img.data());
      static int call = 0;
      img.write(std::string(debug) + "_" + std::to_string(call++) + "_" + std::to_string(mi) + "_" +
                    std::to_string(pi) + ".png",
                OIIO::TypeDesc::UINT8);
    }
  }
  return r;
}

// ---------------------------------------------------------------- helpers

tinygltf::Model load(const std::string& path) {
  tinygltf::Model m;
  const GltfReadResult r = read_gltf(path, m);
  if (!r.ok) fail(path + ": " + r.error);
  return m;
}

void save(tinygltf::Model m, const std::string& path) {
  const std::string e = write_gltf(m, path);
  if (!e.empty()) fail(path + ": " + e);
}

// Bytes of all images of a model.
size_t image_bytes(const tinygltf::Model& m) {
  size_t n = 0;
  for (const auto& im : m.images) {
    if (!im.image.empty())
      n += im.image.size();
    else if (im.bufferView >= 0)
      n += m.bufferViews[im.bufferView].byteLength;
  }
  return n;
}

// Replaces every image by `bytes` (mime given).
void replace_images(tinygltf::Model& m,
                    const std::function<std::vector<uint8_t>(const std::vector<uint8_t>&)>& f,
                    const std::string& mime) {
  for (auto& im : m.images) {
    std::vector<uint8_t> bytes = im.image;
    if (bytes.empty() && im.bufferView >= 0) {
      const auto& bv = m.bufferViews[im.bufferView];
      const auto& buf = m.buffers[bv.buffer].data;
      bytes.assign(buf.begin() + bv.byteOffset, buf.begin() + bv.byteOffset + bv.byteLength);
    }
    im.image = f(bytes);
    im.as_is = true;
    im.bufferView = -1;
    im.uri.clear();
    im.mimeType = mime;
    im.width = im.height = -1;
  }
  compact_buffers(m);
}

struct Timed {
  tinygltf::Model model;
  EncodeReport report;
  double seconds = 0;
};

Timed encode(const tinygltf::Model& src, const EncodeOptions& o) {
  Timed t;
  t.model = src;
  const double t0 = now_s();
  const std::string e = encode_model(t.model, o, t.report).message;
  t.seconds = now_s() - t0;
  if (!e.empty()) fail("encode_model: " + e);
  return t;
}

tinygltf::Model decode(const tinygltf::Model& enc, double* seconds = nullptr) {
  tinygltf::Model m = enc;
  DecodeReport rep;
  const double t0 = now_s();
  const std::string e = decode_model(m, {}, rep).message;
  if (seconds) *seconds = now_s() - t0;
  if (!e.empty()) fail("decode_model: " + e);
  return m;
}

std::vector<uint8_t> read_view(const tinygltf::Model& m, int view) {
  const auto& bv = m.bufferViews[view];
  const auto& buf = m.buffers[bv.buffer].data;
  return {buf.begin() + bv.byteOffset, buf.begin() + bv.byteOffset + bv.byteLength};
}

float first_texel_scale(const tinygltf::Model& m) {
  for (const auto& mesh : m.meshes)
    for (const auto& p : mesh.primitives) {
      auto it = p.extensions.find(ext::kName);
      if (it == p.extensions.end()) continue;
      const int view = it->second.Get(ext::kBufferView).GetNumberAsInt();
      const std::vector<uint8_t> bytes = read_view(m, view);
      UvStreamInfo info;
      if (read_uvmap_info(bytes, info) == UvStatus::ok) return info.texel_scale;
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"In-process measurements for scripts/bench (one model, JSON on stdout)"};
  std::string input, work;
  int runs = 7;
  bool rd = true;
  app.add_option("input", input, "Source .gltf or .glb")->required()->check(CLI::ExistingFile);
  app.add_option("--work", work, "Directory for the files handed to gltfpack / draco_decoder")->required();
  app.add_option("--runs", runs, "Decode runs (median)")->check(CLI::Range(1, 101));
  app.add_flag("!--no-rd", rd, "Skip the rate-distortion variants (texture settings) for the plot");
  CLI11_PARSE(app, argc, argv);
  fs::create_directories(work);

  const tinygltf::Model src = load(input);
  json out;
  out["file"] = input;
  size_t tris = 0, verts = 0;
  for (const auto& mesh : src.meshes)
    for (const auto& p : mesh.primitives) {
      PrimitiveGeometry g;
      if (!is_triangle_mode(p.mode) || !read_primitive(src, p, g).empty()) continue;
      tris += g.triangles.size() / 3;
      verts += g.vertex_count();
    }
  out["triangles"] = tris;
  out["vertices"] = verts;

  // Ours, default options.
  const EncodeOptions defaults;
  Timed ours = encode(src, defaults);
  std::vector<std::pair<int, int>> replaced;
  size_t bitstream = 0, unmatched = 0;
  uint32_t patches = 0;
  double maxd = 0;
  for (const auto& p : ours.report.primitives)
    if (p.handling == Handling::implicit_uv) {
      replaced.push_back({p.mesh, p.primitive});
      bitstream += p.bitstream_bytes;
      patches += p.patches;
      maxd = std::max(maxd, p.max_distortion);
      unmatched += p.unmatched_faces;
    }
  double fill_num = 0, fill_den = 0;
  for (const auto& a : ours.report.atlases)
    for (const auto& [w, h] : a.page_sizes) {
      fill_num += a.fill * double(w) * h;
      fill_den += double(w) * h;
    }
  const std::string ours_path = work + "/ours.glb";
  save(ours.model, ours_path);
  out["primitives_replaced"] = replaced.size();
  size_t quality_fallback = 0;  // textured primitives the quality floor left with explicit UVs
  for (const auto& p : ours.report.primitives)
    if (p.handling == Handling::fallback && p.fallback.reason == FallbackReason::below_quality_floor)
      ++quality_fallback;
  out["primitives_quality_fallback"] = quality_fallback;
  out["bitstream_bytes"] = bitstream;
  out["patches"] = patches;
  out["max_distortion"] = maxd;
  out["atlas_fill"] = fill_den > 0 ? fill_num / fill_den : 0.0;
  out["unmatched_faces"] = unmatched;
  out["encode_s"] = ours.seconds;
  out["image_bytes_original"] = image_bytes(src);
  out["image_bytes_ours"] = image_bytes(load(ours_path));
  out["file_bytes_ours"] = file_size(ours_path);

  // Explicit-UV costs per replaced primitive, in-process Draco.
  size_t uv_draco[3] = {0, 0, 0}, tangent = 0;
  const int bits[3] = {10, 12, 14};
  for (auto [mi, pi] : replaced) {
    PrimitiveGeometry g;
    if (!read_primitive(src, src.meshes[mi].primitives[pi], g).empty()) fail("read_primitive");
    // Both sides welded (byte-identical vertices merged), so duplicates the source file happens
    // to carry are not charged to the UVs.
    std::vector<VertexAttribute> with_uv = without(g.attributes, {"TANGENT"});
    std::vector<uint32_t> with_uv_tris = g.triangles;
    weld_vertices(with_uv, with_uv_tris);
    std::vector<VertexAttribute> no_uv = without(g.attributes, {"TANGENT", "TEXCOORD_0"});
    std::vector<uint32_t> no_uv_tris = g.triangles;
    weld_vertices(no_uv, no_uv_tris);
    for (int b = 0; b < 3; ++b) {
      DracoOptions o;
      o.texcoord_bits = bits[b];
      const size_t a = draco_bytes(with_uv, with_uv_tris, o), z = draco_bytes(no_uv, no_uv_tris, o);
      uv_draco[b] += a > z ? a - z : 0;
    }
    if (g.find("TANGENT")) {
      const std::vector<VertexAttribute> no_tangent = without(g.attributes, {"TANGENT"});
      const size_t a = draco_bytes(g.attributes, g.triangles, {}),
                   z = draco_bytes(no_tangent, g.triangles, {});
      tangent += a > z ? a - z : 0;
    }
  }
  {  // The same primitives as OBJ (v, vn, vt per source vertex) for the draco_encoder CLI cross-check.
    std::ofstream with_uv(work + "/uv.obj"), no_uv(work + "/nouv.obj");
    size_t base = 0;
    for (auto [mi, pi] : replaced) {
      PrimitiveGeometry g;
      if (!read_primitive(src, src.meshes[mi].primitives[pi], g).empty()) fail("read_primitive");
      const std::vector<float> p = as_floats(*g.find("POSITION")), t = as_floats(*g.find("TEXCOORD_0"));
      const VertexAttribute* na = g.find("NORMAL");
      const std::vector<float> n = na ? as_floats(*na) : std::vector<float>{};
      for (size_t v = 0; v < g.vertex_count(); ++v) {
        char line[256];
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p[3 * v], p[3 * v + 1], p[3 * v + 2]);
        with_uv << line;
        no_uv << line;
        if (na) {
          std::snprintf(line, sizeof line, "vn %.9g %.9g %.9g\n", n[3 * v], n[3 * v + 1], n[3 * v + 2]);
          with_uv << line;
          no_uv << line;
        }
        std::snprintf(line, sizeof line, "vt %.9g %.9g\n", t[2 * v], 1.0f - t[2 * v + 1]);
        with_uv << line;
      }
      for (size_t f = 0; f < g.triangles.size(); f += 3) {
        with_uv << 'f';
        no_uv << 'f';
        for (int k = 0; k < 3; ++k) {
          const size_t i = base + g.triangles[f + k] + 1;
          with_uv << ' ' << i << '/' << i;
          no_uv << ' ' << i;
          if (na) {
            with_uv << '/' << i;
            no_uv << "//" << i;
          }
        }
        with_uv << '\n';
        no_uv << '\n';
      }
      base += g.vertex_count();
    }
  }
  out["uv_draco10"] = uv_draco[0];
  out["uv_draco12"] = uv_draco[1];
  out["uv_draco14"] = uv_draco[2];
  out["tangent_bytes_saved"] = tangent;

  // Files for gltfpack: geometry only (1x1 PNG images), with and without TEXCOORD_0.
  {
    static const std::vector<uint8_t> kPng = [] {
      OIIO::ImageBuf one(OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::UINT8));
      std::vector<uint8_t> b;
      if (!encode_image(one, ImageEncodeOptions{}, b).empty()) fail("1x1 png");
      return b;
    }();
    tinygltf::Model a = src;
    replace_images(
        a, [](const std::vector<uint8_t>&) { return kPng; }, "image/png");
    tinygltf::Model b = a;
    for (auto [mi, pi] : replaced) {
      a.meshes[mi].primitives[pi].attributes.erase("TANGENT");
      b.meshes[mi].primitives[pi].attributes.erase("TANGENT");
      b.meshes[mi].primitives[pi].attributes.erase("TEXCOORD_0");
    }
    compact_buffers(a);
    compact_buffers(b);
    save(a, work + "/geom_uv.glb");
    save(b, work + "/geom_nouv.glb");
  }

  // Draco-12 explicit UVs with the original images.
  EncodeOptions explicit12;
  explicit12.implicit_uvs = false;
  explicit12.draco.texcoord_bits = 12;
  Timed d12 = encode(src, explicit12);
  const std::string d12_path = work + "/draco12.glb";
  save(d12.model, d12_path);
  out["file_bytes_draco12"] = file_size(d12_path);
  {  // first Draco primitive as a .drc for draco_decoder
    const tinygltf::Model m = load(d12_path);
    for (const auto& mesh : m.meshes) {
      bool done = false;
      for (const auto& p : mesh.primitives) {
        auto it = p.extensions.find(kDracoExtension);
        if (it == p.extensions.end()) continue;
        const std::vector<uint8_t> bytes = read_view(m, it->second.Get("bufferView").GetNumberAsInt());
        std::ofstream(work + "/draco12_prim0.drc", std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        done = true;
        break;
      }
      if (done) break;
    }
  }

  // Decode timing, same process, interleaved, median of `runs`.
  const tinygltf::Model ours_file = load(ours_path), d12_file = load(d12_path);
  std::vector<double> t_ours, t_d12;
  tinygltf::Model ours_dec, d12_dec;
  for (int r = 0; r < runs; ++r) {
    double a = 0, b = 0;
    ours_dec = decode(ours_file, &a);
    d12_dec = decode(d12_file, &b);
    t_ours.push_back(a);
    t_d12.push_back(b);
  }
  out["decode_s"] = median(t_ours);
  out["draco12_decode_s"] = median(t_d12);
  out["decode_ratio"] = median(t_d12) > 0 ? median(t_ours) / median(t_d12) : 0.0;
  out["decode_runs"] = runs;

  // Quality.
  const Psnr q_ours = texture_psnr(src, ours_dec, replaced, defaults.draco.position_bits);
  const Psnr q_d12 = texture_psnr(src, d12_dec, replaced, explicit12.draco.position_bits);
  out["psnr_ours"] = q_ours.value();
  out["psnr_draco12"] = q_d12.value();
  out["psnr_samples"] = q_ours.samples;
  out["psnr_faces_skipped"] = q_ours.faces_skipped;

  // Rate-distortion points for the plot.
  json points = json::array();
  points.push_back(
      {{"codec", "ours"}, {"setting", "default"}, {"bytes", file_size(ours_path)}, {"psnr", q_ours.value()}});
  points.push_back({{"codec", "draco12"},
                    {"setting", "original images"},
                    {"bytes", file_size(d12_path)},
                    {"psnr", q_d12.value()}});
  if (rd && !replaced.empty()) {
    const float scale = first_texel_scale(ours.model);
    struct Variant {
      std::string name;
      std::string format;
      int quality;
      double density_factor;
    };
    const std::vector<Variant> vs = {{"jpeg q90", "jpeg", 90, 1},
                                     {"jpeg q75", "jpeg", 75, 1},
                                     {"jpeg q50", "jpeg", 50, 1},
                                     {"png, density x0.5", "png", 0, 0.5},
                                     {"jpeg q75, density x0.5", "jpeg", 75, 0.5}};
    for (const auto& v : vs) {
      EncodeOptions o;
      o.image_format = v.format;
      o.jpeg_quality = v.quality;
      if (v.density_factor != 1) {
        if (!(scale > 0)) continue;
        o.texel_density = scale * v.density_factor;
      }
      Timed t = encode(src, o);
      const std::string p = work + "/ours_variant.glb";
      save(t.model, p);
      const Psnr q = texture_psnr(src, decode(load(p)), replaced, o.draco.position_bits);
      points.push_back(
          {{"codec", "ours"}, {"setting", v.name}, {"bytes", file_size(p)}, {"psnr", q.value()}});
    }
    for (int quality : {90, 75, 50}) {
      tinygltf::Model m = load(d12_path);
      replace_images(
          m,
          [&](const std::vector<uint8_t>& bytes) {
            DecodedImage d;
            if (!decode_image(bytes, d).empty()) fail("decode source image");
            ImageEncodeOptions eo;
            eo.codec = ImageCodec::jpeg;
            eo.jpeg_quality = quality;
            std::vector<uint8_t> b;
            if (!encode_image(d.pixels, eo, b).empty()) fail("encode jpeg");
            return b;
          },
          "image/jpeg");
      const std::string p = work + "/draco12_variant.glb";
      save(m, p);
      const Psnr q = texture_psnr(src, decode(load(p)), replaced, explicit12.draco.position_bits);
      points.push_back({{"codec", "draco12"},
                        {"setting", "jpeg q" + std::to_string(quality)},
                        {"bytes", file_size(p)},
                        {"psnr", q.value()}});
    }
  }
  out["rd"] = points;
  std::printf("%s\n", out.dump(1).c_str());
  return 0;
}
