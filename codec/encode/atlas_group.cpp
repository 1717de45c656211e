// The per-atlas-group steps of the encoder: texel density, packing, the
// bitstream, UVs from decode_uvs (the decoder's own function), then the
// warp of every TEXCOORD_0 texture and the material retargeting.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "codec/decode/tangents.h"
#include "codec/encode/atlas/pack.h"
#include "codec/encode/atlas/pages.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/implicit_uv_encoder.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/png_palette.h"
#include "codec/encode/texture/texture_sampler.h"
#include "codec/encode/texture/warp.h"
#include "codec/encode/texture/warp_quality.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "format/gltf/draco_geometry.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_materials.h"

namespace gltfwarp {
namespace {

// Keep each image's format unless asked otherwise (judged by its bytes: a
// URI image often has no mimeType); formats we do not write (WebP, ...)
// become PNG.
std::string output_mime(std::span<const uint8_t> source, const std::string& wanted) {
  if (wanted == "png") return "image/png";
  if (wanted == "jpeg") return "image/jpeg";
  return sniff_image_codec(source) == ImageCodec::jpeg ? "image/jpeg" : "image/png";
}

// The palette a warped atlas is written with. "PNG stays PNG" keeps a
// source's indexed storage too: an indexed source gives its own palette,
// and a truecolour source drawn from few colours (flat-shaded art) gives its
// most frequent ones (dominant_colours). The warp's filtered edges would
// otherwise bring hundreds of new colours: Fox's atlas 31.7 -> 18.9 KB
// against its 26.8 KB source. Empty: truecolour.
std::vector<PaletteEntry> source_palette(std::span<const uint8_t> source_bytes,
                                         const OIIO::ImageBuf& source) {
  std::vector<PaletteEntry> palette = png_palette(source_bytes);
  if (palette.empty()) palette = dominant_colours(source);
  return palette;
}

// Whether an atlas is written with its source's palette: PNG kept as PNG,
// 8-bit colour, and not a normal map (its texels are re-expressed in new
// frames, so they leave any palette).
bool palette_applies(const OIIO::ImageBuf& atlas, const std::string& mime, bool normal_map,
                     const std::string& wanted) {
  const OIIO::ImageSpec& spec = atlas.spec();
  return mime == "image/png" && wanted == "keep" && !normal_map && spec.format == OIIO::TypeDesc::UINT8 &&
         spec.nchannels >= 3;
}

// Encodes a warped atlas: indexed with `palette` when it has entries (the
// atlas is then already snapped to it), else in its output format.
std::string encode_atlas(const OIIO::ImageBuf& atlas, std::span<const PaletteEntry> palette,
                         const std::string& mime, int quality, std::vector<uint8_t>& bytes) {
  if (!palette.empty()) return encode_indexed_png(atlas, palette, bytes);
  std::string err;
  encode_image(atlas, mime, quality, bytes, err);
  return err;
}

// Tangent frames of one primitive for re-expressing a normal map: the
// frame of the source UVs and the frame of the new UVs, per corner.
struct TangentFrames {
  std::vector<float> normals, old_tangents, new_tangents;
};

TangentFrames corner_frames(const ImplicitPrimitive& ip) {
  TangentFrames f;
  if (const VertexAttribute* n = ip.decoded.find("NORMAL"); n && n->components == 3) {
    f.normals.resize(ip.decoded.triangles.size() * 3);
    for (size_t c = 0; c < ip.decoded.triangles.size(); ++c)
      for (int i = 0; i < 3; ++i) f.normals[3 * c + i] = n->get(ip.decoded.triangles[c], i);
  } else {
    f.normals = flat_corner_normals(ip.tri);
  }
  // The source's own TANGENT when it has one: viewers light it in that frame.
  f.old_tangents =
      ip.source_tangents.empty() ? corner_tangents(ip.tri, f.normals, ip.source_uv) : ip.source_tangents;
  f.new_tangents = corner_tangents(ip.tri, f.normals, ip.corner_uv);
  return f;
}

int add_clamp_sampler(tinygltf::Model& model) {
  tinygltf::Sampler s;
  s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  s.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  s.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(s);
  return static_cast<int>(model.samplers.size() - 1);
}

}  // namespace

// Largest image (by texel count) that the primitive's TEXCOORD_0 slots
// sample, as its UVs see it: a KHR_texture_transform scales the
// texels per UV unit (gltfpack writes UVs quantized to [0, 1/16] with a
// 16x transform), so its scale is folded into the size. 0 x 0 when none has
// a readable size. Also used by prepare_implicit_primitive
// (implicit_uv_encoder.cpp) for the partition's density rule, so both see
// the same per-face density.
void largest_uv0_image(const tinygltf::Model& model, const tinygltf::Primitive& prim, uint32_t& width,
                       uint32_t& height) {
  width = height = 0;
  double best = 0;
  for (const auto& s : primitive_uv0_slots(model, prim)) {
    const int image = texture_image(model, s.texture);
    int iw = 0, ih = 0;
    std::string err;
    if (!image_size(model.images[image].image, iw, ih, err) || iw <= 0 || ih <= 0) continue;
    // Texels per UV unit along u and v: exact for an axis-aligned transform
    // (scale, offset, half turns), the area-preserving mean when it turns.
    const auto& m = s.transform;
    double su = std::abs(m[0]), sv = std::abs(m[4]);
    if (m[1] != 0 || m[3] != 0) su = sv = std::sqrt(std::abs(m[0] * m[4] - m[1] * m[3]));
    if (!std::isfinite(su) || !std::isfinite(sv)) continue;
    constexpr double kMaxSide = double(1 << 24);
    const double ew = std::clamp(iw * su, 1.0, kMaxSide), eh = std::clamp(ih * sv, 1.0, kMaxSide);
    if (ew * eh > best) {
      best = ew * eh;
      width = static_cast<uint32_t>(std::lround(ew));
      height = static_cast<uint32_t>(std::lround(eh));
    }
  }
}

namespace {

// Slot sources are warped once per distinct (image, sampler, transform,
// colour space, normal map).
using JobKey = std::tuple<int, int, std::array<double, 6>, int, bool>;

struct WarpJob {
  JobKey key;
  int image = -1;
  uint32_t page = 0;
  std::vector<uint8_t> bytes;  // the encoded atlas image
  std::string mime;
};

// One group's atlas at one texel density, built without touching the model,
// so the encoder can measure it and try again or give up.
struct GroupAtlas {
  AtlasReport report;
  std::vector<UvMap> maps;                       // per member
  std::vector<std::vector<uint8_t>> bitstreams;  // per member
  std::vector<WarpJob> jobs;
  SurfaceError error;  // colour slots: warped atlas against the source
  // The same per source image (pages pooled). The quality floor holds for
  // each image, so each material variant (usually its own images) keeps it,
  // not only the group's images on average.
  std::map<int, SurfaceError> image_error;
  double floor_psnr() const {
    double worst = error.values ? error.psnr() : 0;
    for (const auto& [image, e] : image_error)
      if (e.values) worst = std::min(worst, e.psnr());
    return worst;
  }
  bool capped = false;                     // the atlas was shrunk to fit --max-atlas-size
  uint32_t patch_count = 0;                // over the members, numbered member by member
  std::vector<SurfaceError> patch_error;   // per patch, colour slots
  std::vector<double> patch_texels;        // per patch: its triangles' area in atlas texels
  std::vector<std::vector<size_t>> pages;  // members (indices into group.members) per page
  std::vector<uint32_t> page_of_member;
};

// Atlas texels of each group member, estimated the way the packer scales
// each patch: its density against the reference, with its adaptive bias.
std::vector<double> member_texels(const AtlasGroup& group, const ImplicitPlan& plan,
                                  const std::vector<std::vector<double>>& density,
                                  const std::vector<std::vector<int32_t>>& step_bias, double scale,
                                  double reference) {
  std::vector<double> texels(group.members.size(), 0.0);
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    const auto patch = estimated_patch_texels(
        ip.corner_xy, ip.patch_of_face, ip.patch_count,
        reference > 0 ? std::span<const double>(density[k]) : std::span<const double>(),
        reference > 0 ? scale / reference : scale);
    for (uint32_t p = 0; p < ip.patch_count; ++p) {
      const double s = k < step_bias.size() && p < step_bias[k].size() ? patch_scale(step_bias[k][p]) : 1.0;
      texels[k] += patch[p] * s * s;
    }
  }
  return texels;
}

// The group's members spread over at most max_pages pages of `capacity`
// texels (pages.h): whole members only, as a primitive samples one image
// per slot; those too large for a page alone were cut into parts when they
// were prepared (prepare_implicit_primitive). Past max_pages: fewer, fuller
// pages (the packer then shrinks the density where they overflow).
std::vector<std::vector<size_t>> spread_over_pages(std::span<const double> texels, double capacity,
                                                   uint32_t max_pages) {
  if (max_pages <= 1 || texels.size() < 2 || !(capacity > 0)) {
    std::vector<size_t> all(texels.size());
    for (size_t k = 0; k < all.size(); ++k) all[k] = k;
    return {all};
  }
  uint32_t count = 0;
  return within_part_count(
      capacity, max_pages,
      [&](double c, uint32_t& n) {
        auto pages = assign_pages(texels, c);
        n = uint32_t(pages.size());
        return pages;
      },
      count);
}

// Packs each page of out.pages on its own: out.maps, page_of_member and
// capped, and the report's page sizes, fill and overlap. `crowded`: a page
// of several members overflowed (another spread may help); `scale_kept`:
// the lowest page's texel scale over `scale` (1 when none shrank).
std::string pack_pages(const std::vector<PackPrimitive>& pp, const PackOptions& po, double scale,
                       GroupAtlas& out, bool& crowded, double& scale_kept) {
  AtlasReport& ar = out.report;
  out.page_of_member.assign(pp.size(), 0);
  out.maps.assign(pp.size(), UvMap{});
  out.capped = crowded = false;
  scale_kept = 1;
  ar.page_sizes.clear();
  ar.overlapping_texels = 0;
  double covered = 0, page_texels = 0;
  for (size_t page = 0; page < out.pages.size(); ++page) {
    std::vector<PackPrimitive> on_page;
    for (size_t k : out.pages[page]) on_page.push_back(pp[k]);
    PackResult packed;
    const PackStatus ps = pack_atlas(on_page, po, packed);
    if (ps != PackStatus::ok) return std::string("atlas packing failed: ") + to_string(ps);
    for (size_t i = 0; i < out.pages[page].size(); ++i) {
      out.maps[out.pages[page][i]] = packed.maps[i];
      out.page_of_member[out.pages[page][i]] = uint32_t(page);
    }
    ar.page_sizes.push_back({packed.report.atlas_width, packed.report.atlas_height});
    covered += packed.report.fill * double(packed.report.atlas_texels);
    page_texels += double(packed.report.atlas_texels);
    ar.overlapping_texels += packed.report.overlap_texels;
    // The page hit --max-atlas-size and the scale shrank: more density cannot help.
    if (packed.report.shrink_retries > 0) {
      out.capped = true;
      scale_kept = std::min(scale_kept, packed.report.texel_scale / scale);
      crowded = crowded || out.pages[page].size() > 1;
    }
  }
  ar.width = ar.page_sizes[0][0];
  ar.height = ar.page_sizes[0][1];
  ar.fill = page_texels > 0 ? covered / page_texels : 0;
  return {};
}

// Decoded source images by image index: a group's atlas is built up to five
// times (density retries, adaptive rounds), its sources decoded once.
// With each, what every build derives from it alone: its palette and its
// sampler for the quality check (the truck: 12 builds, 0.15 s each).
struct SourceImage {
  OIIO::ImageBuf pixels;
  std::optional<std::vector<PaletteEntry>> palette;  // source_palette, once asked for
  std::map<JobKey, TextureSampler> samplers;
};
using SourceImages = std::map<int, SourceImage>;

// measure_only: the build only measures each patch's texels and error (an
// adaptive round's trial): one packing order, no normal maps, no PNG coding
// (JPEG is still coded: its loss is part of the error).
std::string build_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                              const EncodeOptions& options, SourceImages& sources, double density_factor,
                              const std::vector<std::vector<int32_t>>& step_bias, GroupAtlas& out,
                              bool measure_only = false) {
  out = GroupAtlas{};
  // Patches numbered across the group's members, for per-patch errors.
  std::vector<std::vector<uint32_t>> group_patch(group.members.size());
  for (size_t k = 0, offset = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    for (uint32_t pf : ip.patch_of_face) group_patch[k].push_back(uint32_t(offset + pf));
    offset += ip.patch_count;
    out.patch_count = uint32_t(offset);
  }
  out.patch_error.assign(out.patch_count, SurfaceError{});
  // Texel density: keep the source's detail (largest image each primitive samples).
  std::vector<DensityPrimitive> dens;
  for (size_t m : group.members) {
    const auto& ip = plan.prims[m];
    const auto& prim = model.meshes[ip.mesh].primitives[ip.primitive];
    uint32_t w = 0, h = 0;
    largest_uv0_image(model, prim, w, h);
    dens.push_back({&ip.tri, ip.source_uv, w, h});
  }
  double scale = options.texel_density, reference = 0;
  if (!(scale > 0)) {
    TexelDensityOptions to;
    to.mode = options.texel_budget;
    reference = auto_texel_scale(dens, to).texel_scale;
    scale = reference * density_factor;
  }

  // Per-face density the layout needs (texels per layout unit, so the tau
  // stretch counts) lets the packer give each patch its own scale step:
  // with `auto`, each patch gets its faces' median density.
  std::vector<std::vector<double>> density(group.members.size());
  std::vector<PackPrimitive> pp;
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    density[k] = layout_texel_density(ip.corner_xy, ip.source_uv, dens[k].image_width, dens[k].image_height);
    PackPrimitive p;
    p.mesh = &ip.tri;
    p.patch_of_face = ip.patch_of_face;
    p.patch_count = ip.patch_count;
    p.seeds = ip.seeds;
    p.methods = ip.methods;
    p.solve = ip.solve;
    p.corner_xy = ip.corner_xy;
    p.face_density = density[k];
    if (k < step_bias.size()) p.scale_step_bias = step_bias[k];
    pp.push_back(p);
  }
  PackOptions po;
  po.texel_scale = scale;
  po.density_reference = reference;
  po.gutter = static_cast<uint32_t>(std::max(0, options.gutter));
  po.max_atlas_size = options.max_atlas_size;
  po.rounding = options.power_of_two ? SizeRounding::power_of_two : SizeRounding::multiple_of_4;
  // A measurement needs each patch's texels and error, not the tightest page.
  if (measure_only) po.multi_order_max_patches = 0;
  // Pages by estimate; when a page of several members still overflows (the
  // estimate misses gutters and ragged outlines, which weigh most on small
  // pages), the members spread again over smaller pages, a few times.
  const std::vector<double> texels = member_texels(group, plan, density, step_bias, scale, reference);
  AtlasReport& ar = out.report;
  ar.density_factor = density_factor;
  double scale_kept = 1;  // the lowest page's texel scale, over the one asked for
  double capacity = page_capacity(options.max_atlas_size);
  for (int attempt = 0;; ++attempt, capacity *= 0.75) {
    out.pages = spread_over_pages(texels, capacity, options.max_pages);
    bool crowded = false;
    if (std::string err = pack_pages(pp, po, scale, out, crowded, scale_kept); !err.empty()) return err;
    if (!crowded || attempt >= 3 || out.pages.size() >= std::min<size_t>(options.max_pages, texels.size()))
      break;
  }
  if (out.capped && reference > 0) ar.density_factor = density_factor * scale_kept;

  // Bitstreams, and the UVs exactly as the decoder will rebuild them.
  for (size_t k = 0; k < group.members.size(); ++k) {
    auto& ip = plan.prims[group.members[k]];
    UvMap& map = out.maps[k];
    map.tau = static_cast<float>(options.tau);
    std::vector<uint8_t> bytes;
    UvStatus st = write_uvmap(map, ip.tri, bytes);
    if (st != UvStatus::ok) return std::string("cannot write the UV bitstream: ") + to_string(st);
    st = decode_uvs(ip.tri, bytes, ip.corner_uv);
    if (st != UvStatus::ok) return std::string("the UV bitstream does not decode: ") + to_string(st);
    out.bitstreams.push_back(std::move(bytes));
  }
  out.patch_texels.assign(out.patch_count, 0.0);
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    const UvMap& map = out.maps[k];
    for (size_t f = 0; f < ip.patch_of_face.size(); ++f) {
      const double s = double(map.texel_scale) * patch_scale(map.placements[ip.patch_of_face[f]].scale_step);
      out.patch_texels[group_patch[k][f]] += layout_face_area(ip.corner_xy, f) * s * s;
    }
  }

  // The images each member samples (through any material it can show):
  // only those members paint an image.
  std::vector<std::set<int>> member_images(group.members.size());
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    for (const auto& s : primitive_uv0_slots(model, model.meshes[ip.mesh].primitives[ip.primitive]))
      member_images[k].insert(texture_image(model, s.texture));
  }
  std::set<JobKey> warped;
  for (int mat : group.materials) {
    for (const auto& slot : texture_slots(model, mat)) {
      if (slot.tex_coord != 0) continue;
      const int image = texture_image(model, slot.texture);
      const int sampler = model.textures[slot.texture].sampler;
      const JobKey key{image, sampler, slot.transform, static_cast<int>(slot.color_space), slot.normal_map};
      if (!warped.insert(key).second) continue;
      std::string err;
      auto [found, fresh] = sources.try_emplace(image);
      if (fresh && !decode_image(model.images[image].image, found->second.pixels, err)) {
        sources.erase(found);
        return "image " + std::to_string(image) + ": " + err;
      }
      SourceImage& cached = found->second;
      const OIIO::ImageBuf& source = cached.pixels;
      if (measure_only && slot.normal_map) continue;  // measured on colour slots only
      WarpOptions wo;
      wo.encoding = slot.normal_map
                        ? SlotEncoding::normal
                        : (slot.color_space == ColorSpace::srgb ? SlotEncoding::srgb : SlotEncoding::linear);
      int gl_wrap_s = 0, gl_wrap_t = 0;
      texture_wraps(model, slot.texture, gl_wrap_s, gl_wrap_t);
      wo.wrap_s = wrap_from_gltf(gl_wrap_s);
      wo.wrap_t = wrap_from_gltf(gl_wrap_t);
      for (int i = 0; i < 6; ++i) wo.uv_transform[i] = static_cast<float>(slot.transform[i]);
      wo.gutter = static_cast<uint32_t>(std::max(0, options.gutter));
      const std::string mime = output_mime(model.images[image].image, options.image_format);
      wo.empty_fill = mime == "image/jpeg" ? EmptyFill::pull_push : EmptyFill::mean;
      ar.source_image_bytes += model.images[image].image.size();
      for (size_t page = 0; page < out.pages.size(); ++page) {
        std::vector<WarpPrimitive> wp;
        std::vector<SurfaceUvs> uvs;
        std::vector<TangentFrames> frames;
        frames.reserve(group.members.size());
        for (size_t k : out.pages[page]) {
          if (!member_images[k].count(image)) continue;
          const auto& ip = plan.prims[group.members[k]];
          WarpPrimitive w;
          w.source_uv = ip.source_uv;
          w.atlas_uv = ip.corner_uv;
          if (slot.normal_map) {
            frames.push_back(corner_frames(ip));
            w.normals = frames.back().normals;
            w.old_tangents = frames.back().old_tangents;
            w.new_tangents = frames.back().new_tangents;
          }
          wp.push_back(w);
          uvs.push_back({ip.source_uv, ip.corner_uv, group_patch[k]});
        }
        if (wp.empty()) continue;  // no member on this page samples the image
        OIIO::ImageBuf atlas;
        WarpReport wr;
        const auto [page_width, page_height] = ar.page_sizes[page];
        const WarpStatus ws = warp_texture(source, wp, page_width, page_height, wo, atlas, &wr);
        if (ws != WarpStatus::ok)
          return "warping image " + std::to_string(image) + ": " + to_string(ws) +
                 (wr.error.empty() ? "" : " " + wr.error);
        WarpJob job;
        job.key = key;
        job.image = image;
        job.page = uint32_t(page);
        job.mime = mime;
        // Snapped before the quality check, so that it measures the texels the file will hold.
        std::span<const PaletteEntry> palette;
        if (palette_applies(atlas, job.mime, slot.normal_map, options.image_format)) {
          if (!cached.palette) cached.palette = source_palette(model.images[image].image, source);
          palette = *cached.palette;
        }
        snap_to_palette(atlas, palette);
        int quality = options.jpeg_quality;
        if (quality <= 0) quality = estimate_jpeg_quality(model.images[image].image);
        if (quality <= 0) quality = 90;
        // JPEG is lossy: the check measures the decoded bytes, what a viewer
        // will show (Duck as JPEG q60: 41.8 dB before coding, 35.8 after).
        const bool lossy = job.mime == "image/jpeg" && !slot.normal_map;
        OIIO::ImageBuf decoded;
        if (lossy) {
          err = encode_atlas(atlas, palette, job.mime, quality, job.bytes);
          if (err.empty() && !decode_image(job.bytes, decoded, err))
            err = "cannot read back the coded atlas: " + err;
          if (!err.empty()) return "image " + std::to_string(image) + ": " + err;
        }
        if (!slot.normal_map) {
          // Normal maps change legitimately (new tangent frames): colour slots only.
          const bool srgb = slot.color_space == ColorSpace::srgb;
          auto [sit, fresh_sampler] = cached.samplers.try_emplace(key);
          if (fresh_sampler)
            load_texture_sampler(source, srgb, gl_wrap_s, gl_wrap_t, slot.transform, sit->second);
          const TextureSampler& before = sit->second;
          TextureSampler after;
          load_texture_sampler(lossy ? decoded : atlas, srgb, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE,
                               TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE, {1, 0, 0, 0, 1, 0}, after);
          const SurfaceError e = surface_error(before, after, uvs, 4'000'000, &out.patch_error);
          out.error.add(e);
          out.image_error[image].add(e);
        }
        if (!measure_only && !lossy) err = encode_atlas(atlas, palette, job.mime, quality, job.bytes);
        if (!err.empty()) return "image " + std::to_string(image) + ": " + err;
        ar.atlas_image_bytes += job.bytes.size();
        out.jobs.push_back(std::move(job));
      }
    }
  }
  ar.psnr = out.floor_psnr();
  return {};
}

// The group's primitives get their bitstreams, its materials the atlases.
void commit_group_atlas(tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                        GroupAtlas& built, EncodeReport& report, int& clamp_sampler,
                        std::vector<int>& retired_textures) {
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    const UvMap& map = built.maps[k];
    auto& prim = model.meshes[ip.mesh].primitives[ip.primitive];
    tinygltf::Value::Object obj;
    obj[ext::kBufferView] = tinygltf::Value(add_buffer_view(model, built.bitstreams[k]));
    obj[ext::kTexCoord] = tinygltf::Value(0);
    obj[ext::kAtlasWidth] = tinygltf::Value(static_cast<int>(map.atlas_width));
    obj[ext::kAtlasHeight] = tinygltf::Value(static_cast<int>(map.atlas_height));
    if (ip.had_tangents) obj["tangents"] = tinygltf::Value(true);
    prim.extensions[ext::kName] = tinygltf::Value(obj);
    declare_extension(model, ext::kName, true);
    auto& pr = report.primitives[ip.report_index];
    pr.bitstream_bytes = built.bitstreams[k].size();
    pr.atlas = static_cast<int>(report.atlases.size());
  }
  // Each page's members sample that page's images: the first page a
  // material is used on keeps it, every later page gets a copy of it (taken
  // before any slot is retargeted). A group material no member uses follows
  // the first page, as with one page.
  std::map<std::pair<int, uint32_t>, int> material_on_page;  // (group material, page) -> material
  std::set<int> placed;
  for (uint32_t page = 0; page < built.pages.size(); ++page)
    for (size_t k : built.pages[page]) {
      const auto& ip = plan.prims[group.members[k]];
      auto& prim = model.meshes[ip.mesh].primitives[ip.primitive];
      for (const int mat : primitive_materials(prim)) {  // its own and its variants'
        if (std::find(group.materials.begin(), group.materials.end(), mat) == group.materials.end()) continue;
        auto [it, fresh] = material_on_page.try_emplace({mat, page}, mat);
        if (fresh && !placed.insert(mat).second) {
          tinygltf::Material copy = model.materials[mat];
          copy.name += (copy.name.empty() ? "page " : " (page ") + std::to_string(page + 1) +
                       (copy.name.empty() ? "" : ")");
          model.materials.push_back(std::move(copy));
          it->second = static_cast<int>(model.materials.size() - 1);
        }
        replace_primitive_material(prim, mat, it->second);
      }
    }
  for (int mat : group.materials)
    if (placed.insert(mat).second) material_on_page[{mat, 0}] = mat;
  std::map<std::pair<JobKey, uint32_t>, int> made;  // (slot source, page) -> new texture
  for (WarpJob& job : built.jobs) {
    tinygltf::Image img;
    const auto& src = model.images[job.image];
    img.name = src.name.empty() ? "atlas" : src.name + "_atlas";
    if (job.page > 0) img.name += std::to_string(job.page + 1);
    img.mimeType = job.mime;
    img.image = std::move(job.bytes);
    img.as_is = true;
    model.images.push_back(std::move(img));
    if (clamp_sampler < 0) clamp_sampler = add_clamp_sampler(model);
    tinygltf::Texture tex;
    tex.source = static_cast<int>(model.images.size() - 1);
    tex.sampler = clamp_sampler;
    model.textures.push_back(tex);
    made[{job.key, job.page}] = static_cast<int>(model.textures.size() - 1);
  }
  // Slots as the source had them: retargeting must not change what later
  // slots see.
  std::map<int, std::vector<TextureSlot>> source_slots;
  for (int mat : group.materials) source_slots[mat] = texture_slots(model, mat);
  for (const auto& [mat_page, target] : material_on_page)
    for (TextureSlot slot : source_slots[mat_page.first]) {
      if (slot.tex_coord != 0) continue;
      const JobKey key{texture_image(model, slot.texture), model.textures[slot.texture].sampler,
                       slot.transform, static_cast<int>(slot.color_space), slot.normal_map};
      const auto it = made.find({key, mat_page.second});
      if (it == made.end()) continue;
      retired_textures.push_back(slot.texture);
      slot.material = target;
      retarget_slot(model, slot, it->second);
    }
  report.atlases.push_back(built.report);
}

// The group's primitive goes back to explicit UVs: its source accessors
// (still in the model until compact_buffers) are written as plain Draco, or
// raw, like any primitive without implicit UVs.
std::string restore_explicit_uvs(tinygltf::Model& model, const ImplicitPrimitive& ip,
                                 const EncodeOptions& options, std::vector<int>& replaced,
                                 PrimitiveReport& pr, const std::string& why) {
  tinygltf::Primitive& prim = model.meshes[ip.mesh].primitives[ip.primitive];
  PrimitiveGeometry geom;
  pr.geometry_bytes = 0;
  pr.bitstream_bytes = 0;
  pr.patches = 0;
  pr.atlas = -1;
  if (std::string err =
          rewrite_explicit(model, prim, ip.source_primitive, options, replaced, geom, pr.geometry_bytes);
      !err.empty())
    return err;
  pr.handling = "fallback: explicit UVs kept (" + why + ")";
  return {};
}

// What the primitive's geometry costs with its explicit UVs: the source
// primitive as restore_explicit_uvs would write it (Draco, or raw arrays).
// 0 when it cannot be measured (the comparison then favours the atlas).
size_t explicit_geometry_bytes(const tinygltf::Model& model, const ImplicitPrimitive& ip,
                               const EncodeOptions& options) {
  PrimitiveGeometry geom;
  if (!read_primitive(model, ip.source_primitive, geom).empty()) return 0;
  if (options.raw_geometry) return plain_geometry_bytes(geom);
  if (!non_finite_attribute(geom).empty()) return 0;
  const DracoEncoded enc = draco_encode(geom.attributes, geom.triangles, options.draco);
  return enc.error.empty() ? enc.bytes.size() : 0;
}

// Bytes of the source images that the group's atlas would make redundant:
// images whose every use, in every material, is a TEXCOORD_0 slot of one of
// the group's materials. An image that something else samples stays in the
// file whatever the group does.
size_t replaceable_source_bytes(const tinygltf::Model& model, const AtlasGroup& group,
                                const GroupAtlas& built) {
  std::set<int> images;
  for (const WarpJob& job : built.jobs) images.insert(job.image);
  for (int m = 0; m < int(model.materials.size()); ++m) {
    const bool ours = std::find(group.materials.begin(), group.materials.end(), m) != group.materials.end();
    for (const TextureSlot& slot : texture_slots(model, m))
      if (!ours || slot.tex_coord != 0) images.erase(texture_image(model, slot.texture));
  }
  size_t bytes = 0;
  for (int i : images) bytes += model.images[i].image.size();
  return bytes;
}

// Smooth content keeps its quality with fewer texels. Each round measures
// every patch at two scale steps less than now (half its texels), then
// gives the smaller scale to the patches that buy the most texels for the
// least added error, while the group's error stays under the floor (plus
// half a dB of margin), and while the images are already no larger than
// their sources, above the quality goal too (or where it is, if below). A
// round's result is kept only if its own measurement holds the floor and its
// images are smaller; otherwise the previous atlas is rebuilt and the search
// stops.
std::string spend_quality_headroom(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                                   const EncodeOptions& options, SourceImages& sources, double factor,
                                   double min_psnr, GroupAtlas& built) {
  constexpr int32_t kStep = -2;
  std::vector<std::vector<int32_t>> bias(group.members.size());
  for (size_t k = 0; k < group.members.size(); ++k)
    bias[k].assign(plan.prims[group.members[k]].patch_count, 0);
  const size_t source_bytes = replaceable_source_bytes(model, group, built);
  bool plan_follows_built = true;  // the plan's UVs are those of the last build
  for (int round = 0; round < options.adaptive_rounds; ++round) {
    // Images already within their sources' bytes give up no quality below
    // the goal: an atlas under it stays as it is, one above it goes no lower.
    double target = min_psnr + 0.5;
    if (built.report.atlas_image_bytes <= source_bytes)
      target = std::max(target, std::min(options.goal_psnr, built.error.psnr()));
    const double budget = double(built.error.values) * 255.0 * 255.0 / std::pow(10.0, target / 10.0);
    std::vector<std::vector<int32_t>> all_down = bias;
    for (auto& b : all_down)
      for (int32_t& step : b) step += kStep;
    GroupAtlas down;
    std::string err = build_group_atlas(model, plan, group, options, sources, factor, all_down, down, true);
    if (!err.empty()) return err;
    plan_follows_built = false;
    if (down.capped || down.patch_error.size() != built.patch_error.size()) break;
    double squared = built.error.squared;
    struct Choice {
      uint32_t patch;
      double added, saved;
    };
    std::vector<Choice> choices;
    for (uint32_t p = 0; p < built.patch_count; ++p) {
      const double saved = built.patch_texels[p] - down.patch_texels[p];
      if (!(saved > 0) || built.patch_error[p].values == 0) continue;
      choices.push_back({p, down.patch_error[p].squared - built.patch_error[p].squared, saved});
    }
    std::sort(choices.begin(), choices.end(), [](const Choice& a, const Choice& b) {
      return a.added * b.saved < b.added * a.saved;  // least added error per texel saved first
    });
    std::vector<uint8_t> lower(built.patch_count, 0);
    size_t taken = 0;
    for (const Choice& c : choices) {
      if (squared + c.added > budget) break;
      squared += c.added;
      lower[c.patch] = 1;
      ++taken;
    }
    if (taken == 0) break;
    std::vector<std::vector<int32_t>> next = bias;
    for (size_t k = 0, offset = 0; k < next.size(); ++k) {
      for (size_t p = 0; p < next[k].size(); ++p)
        if (lower[offset + p]) next[k][p] += kStep;
      offset += next[k].size();
    }
    GroupAtlas chosen;
    err = build_group_atlas(model, plan, group, options, sources, factor, next, chosen);
    if (!err.empty()) return err;
    // Fewer texels usually mean fewer bytes, but not always (a blurred sharp
    // checker compresses worse): keep a round only if the bytes fell too.
    if (chosen.error.values > 0 && chosen.floor_psnr() >= min_psnr && !chosen.capped &&
        chosen.report.atlas_image_bytes < built.report.atlas_image_bytes) {
      built = std::move(chosen);
      bias = std::move(next);
      plan_follows_built = true;
      continue;
    }
    // Back to the last kept atlas (the UVs in the plan follow the last build).
    return build_group_atlas(model, plan, group, options, sources, factor, bias, built);
  }
  // The last build may have been a measurement: the plan's UVs must be built's.
  return plan_follows_built ? std::string()
                            : build_group_atlas(model, plan, group, options, sources, factor, bias, built);
}

}  // namespace

std::string finish_implicit_uvs(tinygltf::Model& model, ImplicitPlan& plan, const EncodeOptions& options,
                                std::vector<int>& replaced, EncodeReport& report) {
  plan.seam_textures.clear();  // the partitions are made
  plan.seam_materials.clear();
  int clamp_sampler = -1;
  std::vector<int> retired_textures;  // source textures the atlases replaced
  const bool auto_density = !(options.texel_density > 0);
  // The quality floor holds by default for the default density only: a
  // chosen density (or factor) is a chosen trade-off.
  const double min_psnr = options.min_psnr >= 0
                              ? options.min_psnr
                              : (auto_density && options.texel_density_factor == 1.0 ? 38.0 : 0.0);
  std::vector<double> factors = {options.texel_density_factor};
  if (auto_density && min_psnr > 0)
    for (double boost : options.density_boosts) factors.push_back(options.texel_density_factor * boost);
  // The group's primitives keep their explicit UVs; the report says why.
  auto keep_explicit = [&](const AtlasGroup& group, const std::string& why) -> std::string {
    for (size_t m : group.members) {
      auto& pr = report.primitives[plan.prims[m].report_index];
      std::string err = restore_explicit_uvs(model, plan.prims[m], options, replaced, pr, why);
      if (!err.empty()) return err;
      report.notes.push_back("mesh " + std::to_string(pr.mesh) + " primitive " +
                             std::to_string(pr.primitive) + ": " + pr.handling);
      plan.group_of.erase({pr.mesh, pr.primitive});
    }
    return {};
  };
  for (size_t gi = 0; gi < plan.groups.size(); ++gi) {
    auto& group = plan.groups[gi];
    if (group.members.empty()) continue;
    if (options.progress) options.progress("atlas", double(gi) / double(plan.groups.size()));
    GroupAtlas built;
    SourceImages sources;
    double factor_used = factors[0];
    for (double factor : factors) {
      std::string err = build_group_atlas(model, plan, group, options, sources, factor, {}, built);
      if (!err.empty()) return err;
      factor_used = factor;
      if (!(min_psnr > 0) || built.error.values == 0 || built.floor_psnr() >= min_psnr || built.capped) break;
    }
    if (min_psnr > 0 && options.adaptive_density && built.error.values > 0 && !built.capped &&
        built.floor_psnr() >= min_psnr + 0.5) {
      std::string err =
          spend_quality_headroom(model, plan, group, options, sources, factor_used, min_psnr, built);
      if (!err.empty()) return err;
    }
    const double psnr = built.floor_psnr();
    if (min_psnr > 0 && built.error.values > 0 && psnr < min_psnr && options.quality_fallback) {
      char why[160];
      std::snprintf(why, sizeof why,
                    "the warped atlas reached %.1f dB at %.3gx density%s, below --min-psnr %.1f", psnr,
                    built.report.density_factor, built.capped ? " (held by --max-atlas-size)" : "", min_psnr);
      if (std::string err = keep_explicit(group, why); !err.empty()) return err;
      continue;
    }
    // The method exists to save bytes: when the atlas and the bitstreams
    // cost more than the source images and explicit UVs would (fine text,
    // tiny quads carrying big images), keep the explicit UVs.
    if (options.quality_fallback) {
      size_t implicit_bytes = built.report.atlas_image_bytes;
      size_t explicit_bytes = replaceable_source_bytes(model, group, built);
      for (size_t k = 0; k < group.members.size(); ++k) {
        const ImplicitPrimitive& ip = plan.prims[group.members[k]];
        implicit_bytes += report.primitives[ip.report_index].geometry_bytes + built.bitstreams[k].size();
      }
      // Explicit geometry costs a Draco encode to measure; skip it when the
      // saved images alone already outweigh everything the map costs.
      if (implicit_bytes > explicit_bytes)
        for (size_t m : group.members)
          explicit_bytes += explicit_geometry_bytes(model, plan.prims[m], options);
      if (implicit_bytes > explicit_bytes) {
        char why[200];
        std::snprintf(why, sizeof why,
                      "smaller: %zu bytes of geometry and images, against %zu with the implicit map "
                      "and a %.1f dB atlas",
                      explicit_bytes, implicit_bytes, built.floor_psnr());
        if (std::string err = keep_explicit(group, why); !err.empty()) return err;
        continue;
      }
    }
    commit_group_atlas(model, plan, group, built, report, clamp_sampler, retired_textures);
  }
  drop_unused_textures(model, retired_textures);
  if (options.progress) options.progress("atlas", 1.0);
  return {};
}

}  // namespace gltfwarp
