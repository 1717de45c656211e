// The image stages of a group's atlas (group_atlas.h): each TEXCOORD_0
// slot source warped into each page, snapped and coded as the file will
// hold it, and measured as a viewer will show it.
#include <algorithm>
#include <set>

#include "codec/core/layout_report.h"
#include "codec/decode/tangents.h"
#include "codec/encode/group_atlas.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/png_palette.h"
#include "format/gltf/gltf_materials.h"

namespace gltfwarp {
std::string output_mime(std::span<const uint8_t> source, const std::string& wanted) {
  if (wanted == "png") return "image/png";
  if (wanted == "jpeg") return "image/jpeg";
  if (wanted == "webp") return "image/webp";
  return sniff_image_codec(source) == ImageCodec::jpeg ? "image/jpeg" : "image/png";
}

namespace {

// The palette a warped atlas is written with. "PNG stays PNG" keeps a
// source's indexed storage too: an indexed source gives its own palette,
// and a truecolour source drawn from few colours (flat-shaded art) gives its
// most frequent ones (dominant_colours). The warp's filtered edges would
// otherwise bring hundreds of new colours (benchmarks/results: Fox's atlas
// bytes against its source's). Empty: truecolour.
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

// 3D area of each face: the weight of its samples in the least-squares texel fit.
std::vector<float> face_areas(const TriMesh& mesh) {
  std::vector<float> area(mesh.face_count());
  for (uint32_t f = 0; f < mesh.face_count(); ++f) area[f] = static_cast<float>(face_area3(mesh, f));
  return area;
}

}  // namespace

std::vector<SlotSource> slot_sources(const tinygltf::Model& model, const AtlasGroup& group) {
  std::vector<SlotSource> out;
  std::set<JobKey> seen;
  for (int mat : group.materials)
    for (const auto& slot : texture_slots(model, mat)) {
      if (slot.tex_coord != 0) continue;
      const int image = texture_image(model, slot.texture);
      const int sampler = model.textures[slot.texture].sampler;
      const JobKey key{image, sampler, slot.transform, static_cast<int>(slot.color_space), slot.normal_map};
      if (seen.insert(key).second) out.push_back({key, image, slot});
    }
  return out;
}

Error decode_source(const tinygltf::Model& model, int image, SourceImages& sources, SourceImage*& decoded) {
  auto [found, fresh] = sources.try_emplace(image);
  std::string err;
  if (fresh && !decode_image(model.images[image].image, found->second.pixels, err)) {
    sources.erase(found);
    return {ErrorCode::invalid_input, "image " + std::to_string(image) + ": " + err};
  }
  decoded = &found->second;
  return {};
}

SlotCoding slot_coding(const tinygltf::Model& model, const SlotSource& source, const EncodeOptions& options) {
  const TextureSlot& slot = source.slot;
  const std::vector<uint8_t>& bytes = model.images[source.image].image;
  SlotCoding c;
  c.warp.encoding = slot.normal_map
                        ? SlotEncoding::normal
                        : (slot.color_space == ColorSpace::srgb ? SlotEncoding::srgb : SlotEncoding::linear);
  texture_wraps(model, slot.texture, c.gl_wrap_s, c.gl_wrap_t);
  c.warp.wrap_s = wrap_from_gltf(c.gl_wrap_s);
  c.warp.wrap_t = wrap_from_gltf(c.gl_wrap_t);
  for (int i = 0; i < 6; ++i) c.warp.uv_transform[i] = static_cast<float>(slot.transform[i]);
  c.warp.gutter = static_cast<uint32_t>(std::max(0, options.gutter));
  c.warp.least_squares = options.least_squares_texels;
  c.mime = output_mime(bytes, options.image_format);
  // Block coders (JPEG, WebP's VP8) code a smooth fill in fewer bytes. PNG
  // takes nearest copies out to MIP level 3's reach and row runs beyond
  // (EmptyFill::nearest): no level up to 3 tints a patch border with the
  // fill, and the corpus's PNG atlases came out smaller than with the flat
  // mean (benchmarks/results).
  c.warp.empty_fill = lossy_mime(c.mime) ? EmptyFill::pull_push : EmptyFill::nearest;
  c.warp.copy_exact_texels = !lossy_mime(c.mime);
  c.quality = options.image_quality;
  if (c.quality <= 0) c.quality = estimate_jpeg_quality(bytes);
  if (c.quality <= 0) c.quality = 90;
  // A lossy coder: the check measures the decoded bytes, what a viewer will
  // show (benchmarks/results: Duck as JPEG, before and after coding).
  c.lossy = lossy_mime(c.mime) && !slot.normal_map;
  return c;
}

bool samples_image(const tinygltf::Model& model, const ImplicitPrimitive& ip, int image) {
  for (const auto& s : primitive_uv0_slots(model, model.meshes[ip.mesh].primitives[ip.primitive]))
    if (texture_image(model, s.texture) == image) return true;
  return false;
}

const TextureSampler& source_sampler(const SlotSource& source, const SlotCoding& coding,
                                     SourceImage& decoded) {
  auto [it, fresh] = decoded.samplers.try_emplace(source.key);
  if (fresh)
    load_texture_sampler(decoded.pixels, source.slot.color_space == ColorSpace::srgb, coding.gl_wrap_s,
                         coding.gl_wrap_t, source.slot.transform, it->second);
  return it->second;
}

std::vector<SurfaceUvs> page_surface_uvs(const tinygltf::Model& model, const ImplicitPlan& plan,
                                         const AtlasGroup& group, const GroupAtlas& built, int image,
                                         uint32_t page) {
  std::vector<SurfaceUvs> uvs;
  for (size_t k : built.pages[page]) {
    const auto& ip = plan.prims[group.members[k]];
    if (samples_image(model, ip, image))
      uvs.push_back({ip.source_uv, ip.corner_uv, built.group_patch[k], ip.face_area_uv});
  }
  return uvs;
}

bool warp_page_image(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                     const GroupAtlas& built, const SlotSource& source, const SlotCoding& coding,
                     SourceImage& decoded, uint32_t page, OIIO::ImageBuf& atlas, std::vector<SurfaceUvs>& uvs,
                     Error& error, WarpReport* report, LayoutMemo::Entry* kept) {
  error = {};
  uvs.clear();
  const bool normal_map = source.slot.normal_map;
  std::vector<WarpPrimitive> wp;
  std::vector<TangentFrames> frames;
  frames.reserve(group.members.size());
  std::vector<std::vector<float>> areas;
  areas.reserve(group.members.size());
  std::vector<std::vector<uint32_t>> face_pages;  // per member with copies: its faces the warp paints
  face_pages.reserve(group.members.size());
  for (size_t k : built.pages[page]) {
    const auto& ip = plan.prims[group.members[k]];
    // Only the members that sample the image (through any material they can show) paint it.
    if (!samples_image(model, ip, source.image)) continue;
    WarpPrimitive w;
    w.source_uv = ip.source_uv;
    w.atlas_uv = ip.corner_uv;
    areas.push_back(face_areas(ip.tri));
    w.face_area = areas.back();
    // Texel reuse: a copy's faces land on texels its original paints; they
    // paint none of their own (a page no warp produces).
    const UvMap& map = built.maps[k];
    const auto copy = [&](uint32_t p) { return is_texel_copy(ip, map, p); };
    if (std::any_of(ip.patch_of_face.begin(), ip.patch_of_face.end(), copy)) {
      std::vector<uint32_t> pages(ip.patch_of_face.size(), coding.warp.page);
      for (size_t f = 0; f < pages.size(); ++f)
        if (copy(ip.patch_of_face[f])) pages[f] = UINT32_MAX;
      face_pages.push_back(std::move(pages));
      w.page_of_face = face_pages.back();
    }
    if (normal_map) {
      frames.push_back(corner_frames(ip));
      w.normals = frames.back().normals;
      w.old_tangents = frames.back().old_tangents;
      w.new_tangents = frames.back().new_tangents;
    }
    wp.push_back(w);
  }
  uvs = page_surface_uvs(model, plan, group, built, source.image, page);
  if (wp.empty()) return false;
  if (kept && kept->take(source.key, page, atlas, report)) return true;
  std::shared_ptr<const StagedSource>& staged = decoded.staged[coding.warp.encoding];
  if (!staged) {
    std::string why;
    staged = stage_source(decoded.pixels, coding.warp, why);
    if (!staged) {
      error = {ErrorCode::internal, "staging image " + std::to_string(source.image) + ": " + why};
      return true;
    }
  }
  WarpReport wr;
  const auto [page_width, page_height] = built.report.page_sizes[page];
  const WarpStatus ws =
      warp_texture(decoded.pixels, wp, page_width, page_height, coding.warp, atlas, &wr, staged.get());
  if (ws != WarpStatus::ok)
    error = {ErrorCode::internal, "warping image " + std::to_string(source.image) + ": " + to_string(ws) +
                                      (wr.error.empty() ? "" : " " + wr.error)};
  else if (kept)
    kept->keep(source.key, page, atlas, wr);
  if (report) *report = std::move(wr);
  return true;
}

std::span<const PaletteEntry> snap_page_image(const tinygltf::Model& model, const SlotSource& source,
                                              const SlotCoding& coding, const EncodeOptions& options,
                                              SourceImage& decoded, OIIO::ImageBuf& atlas) {
  std::span<const PaletteEntry> palette;
  if (palette_applies(atlas, coding.mime, source.slot.normal_map, options.image_format)) {
    if (!decoded.palette) decoded.palette = source_palette(model.images[source.image].image, decoded.pixels);
    palette = *decoded.palette;
  }
  snap_to_palette(atlas, palette);
  return palette;
}

Error code_page_image(const OIIO::ImageBuf& atlas, std::span<const PaletteEntry> palette,
                      const SlotCoding& coding, std::vector<uint8_t>& bytes) {
  std::string err;
  if (!palette.empty())
    err = encode_indexed_png(atlas, palette, bytes);
  else
    encode_image(atlas, coding.mime, coding.quality, bytes, err);
  return error_if(ErrorCode::internal, err);
}

TextureSampler page_sampler(const SlotSource& source, const OIIO::ImageBuf& shown) {
  TextureSampler out;
  load_texture_sampler(shown, source.slot.color_space == ColorSpace::srgb,
                       TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE,
                       {1, 0, 0, 0, 1, 0}, out);
  return out;
}

void measure_page_image(const SlotSource& source, const SlotCoding& coding, SourceImage& decoded,
                        const OIIO::ImageBuf& shown, std::span<const SurfaceUvs> uvs, GroupAtlas& out) {
  const TextureSampler& before = source_sampler(source, coding, decoded);
  const SurfaceError e = surface_error(before, page_sampler(source, shown), uvs, 4'000'000, &out.patch_error,
                                       &decoded.source_samples[source.key]);
  out.error.add(e);
  out.image_error[source.image].add(e);
}

std::vector<TextureSampler> group_mip_reference(const tinygltf::Model& model, const ImplicitPlan& plan,
                                                const AtlasGroup& group, const SlotSource& source,
                                                const SlotCoding& coding, SourceImage& decoded) {
  std::vector<float> faces;
  for (size_t m : group.members) {
    const ImplicitPrimitive& ip = plan.prims[m];
    if (samples_image(model, ip, source.image))
      faces.insert(faces.end(), ip.source_uv.begin(), ip.source_uv.end());
  }
  return mip_reference(source_sampler(source, coding, decoded), faces);
}

}  // namespace gltfwarp
