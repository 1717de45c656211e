// The layout stages of a group's atlas (group_atlas.h): texel density,
// pages and packing, then the bitstreams and the UVs the decoder rebuilds.
#include <algorithm>
#include <span>

#include "codec/core/parallel.h"
#include "codec/encode/atlas/pack.h"
#include "codec/encode/atlas/pages.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/group_atlas.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"

namespace gltfwarp {
namespace {

// Atlas texels of each group member, estimated the way the packer scales
// each patch: its density against the reference, with its adaptive bias.
std::vector<double> member_texels(const AtlasGroup& group, const ImplicitPlan& plan,
                                  const std::vector<std::vector<double>>& density, const StepBias& step_bias,
                                  double scale, double reference) {
  std::vector<double> texels(group.members.size(), 0.0);
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    const auto patch = estimated_patch_texels(
        ip.corner_xy, ip.patch_of_face, ip.patch_count,
        reference > 0 ? std::span<const double>(density[k]) : std::span<const double>(),
        reference > 0 ? scale / reference : scale);
    for (uint32_t p = 0; p < ip.patch_count; ++p) {
      if (!ip.reuse_of.empty() && ip.reuse_of[p] >= 0) continue;  // a copy: on its original's texels
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
Error pack_pages(const std::vector<PackPrimitive>& pp, const PackOptions& po, double scale, GroupAtlas& out,
                 bool& crowded, double& scale_kept) {
  AtlasReport& ar = out.report;
  out.page_of_member.assign(pp.size(), 0);
  out.maps.assign(pp.size(), UvMap{});
  out.capped = crowded = false;
  scale_kept = 1;
  ar.page_sizes.clear();
  ar.overlapping_texels = 0;
  ar.reused_patches = 0;
  ar.reused_texels = 0;
  ar.aligned_patches = 0;
  double covered = 0, page_texels = 0;
  // Pages are packed side by side (each packing is a pure function of its
  // members): a page whose largest patches take long keeps one core busy.
  std::vector<PackResult> results(out.pages.size());
  std::vector<PackStatus> status(out.pages.size(), PackStatus::ok);
  run_in_parallel(out.pages.size(), worker_count(out.pages.size()), [&](size_t page, size_t) {
    std::vector<PackPrimitive> on_page;
    for (size_t k : out.pages[page]) on_page.push_back(pp[k]);
    status[page] = pack_atlas(on_page, po, results[page]);
  });
  for (size_t page = 0; page < out.pages.size(); ++page) {
    const PackResult& packed = results[page];
    if (status[page] != PackStatus::ok)
      return {ErrorCode::internal, std::string("atlas packing failed: ") + to_string(status[page])};
    for (size_t i = 0; i < out.pages[page].size(); ++i) {
      out.maps[out.pages[page][i]] = packed.maps[i];
      out.page_of_member[out.pages[page][i]] = uint32_t(page);
    }
    ar.page_sizes.push_back({packed.report.atlas_width, packed.report.atlas_height});
    covered += packed.report.fill * double(packed.report.atlas_texels);
    page_texels += double(packed.report.atlas_texels);
    ar.overlapping_texels += packed.report.overlap_texels;
    ar.reused_patches += packed.report.reused_patches;
    ar.reused_texels += packed.report.reused_texels;
    ar.aligned_patches += packed.report.aligned_patches;
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

}  // namespace

void number_patches(const ImplicitPlan& plan, const AtlasGroup& group, GroupAtlas& out) {
  out.group_patch.assign(group.members.size(), {});
  out.patch_count = 0;
  for (size_t k = 0, offset = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    for (uint32_t pf : ip.patch_of_face) out.group_patch[k].push_back(uint32_t(offset + pf));
    offset += ip.patch_count;
    out.patch_count = uint32_t(offset);
  }
  out.patch_error.assign(out.patch_count, SurfaceError{});
}

namespace {

// Texel-exact patches (texel_alignment.h) where every image the primitive's
// TEXCOORD_0 slots sample shares one size, has no texture transform, and
// is written losslessly: a lossy coder spends its bytes on the detail an
// exact copy keeps and a resampling softens (TwoSidedPlane as JPEG q70:
// 17.8 KB at 38.4 dB exact, 15.9 KB at 38.2 dB resampled).
std::pair<uint32_t, uint32_t> align_size(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                         const EncodeOptions& options) {
  if (!options.align_texels) return {0, 0};
  for (const auto& s : primitive_uv0_slots(model, prim))
    if (output_mime(model.images[texture_image(model, s.texture)].image, options.image_format) != "image/png")
      return {0, 0};
  uint32_t w = 0, h = 0;
  aligned_uv0_image(model, prim, w, h);
  return {w, h};
}

}  // namespace

GroupDensity choose_density(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                            const EncodeOptions& options, double density_factor) {
  GroupDensity d;
  d.factor = density_factor;
  std::vector<DensityPrimitive> dens;
  for (size_t m : group.members) {
    const auto& ip = plan.prims[m];
    const auto& prim = model.meshes[ip.mesh].primitives[ip.primitive];
    uint32_t w = 0, h = 0;
    largest_uv0_image(model, prim, w, h);
    dens.push_back({&ip.tri, ip.source_uv, w, h});
    d.align_size.push_back(align_size(model, prim, options));
  }
  d.scale = options.texel_density;
  if (!(d.scale > 0)) {
    TexelDensityOptions to;
    to.mode = options.texel_budget;
    d.reference = auto_texel_scale(dens, to).texel_scale;
    d.scale = d.reference * density_factor;
  }
  // With `auto`, the packer gives each patch its faces' median density.
  d.face_density.resize(group.members.size());
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    d.face_density[k] =
        layout_texel_density(ip.corner_xy, ip.source_uv, dens[k].image_width, dens[k].image_height);
  }
  return d;
}

Error pack_group(const ImplicitPlan& plan, const AtlasGroup& group, const EncodeOptions& options,
                 const GroupDensity& density, const StepBias& step_bias, PackEffort effort, GroupAtlas& out) {
  std::vector<PackPrimitive> pp;
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    PackPrimitive p;
    p.mesh = &ip.tri;
    p.patch_of_face = ip.patch_of_face;
    p.patch_count = ip.patch_count;
    p.seeds = ip.seeds;
    p.methods = ip.methods;
    p.solve = ip.solve;
    p.corner_xy = ip.corner_xy;
    p.reuse_of = ip.reuse_of;
    p.twin_corner = ip.twin_corner;
    p.source_uv = ip.source_uv;
    p.face_density = density.face_density[k];
    if (k < density.align_size.size()) std::tie(p.align_width, p.align_height) = density.align_size[k];
    if (k < step_bias.size()) p.scale_step_bias = step_bias[k];
    pp.push_back(p);
  }
  PackOptions po;
  po.texel_scale = density.scale;
  po.density_reference = density.reference;
  po.gutter = static_cast<uint32_t>(std::max(0, options.gutter));
  po.max_atlas_size = options.max_atlas_size;
  po.rounding = options.power_of_two ? SizeRounding::power_of_two : SizeRounding::multiple_of_16;
  po.orientation = options.orient_to_source ? PatchOrientation::source_axes : PatchOrientation::min_rectangle;
  if (effort == PackEffort::one_order) po.multi_order_max_patches = 0;
  // Pages by estimate; when a page of several members still overflows (the
  // estimate misses gutters and ragged outlines, which weigh most on small
  // pages), the members spread again over smaller pages, a few times.
  const std::vector<double> texels =
      member_texels(group, plan, density.face_density, step_bias, density.scale, density.reference);
  AtlasReport& ar = out.report;
  ar.density_factor = density.factor;
  double scale_kept = 1;  // the lowest page's texel scale, over the one asked for
  double capacity = page_capacity(options.max_atlas_size);
  for (int attempt = 0;; ++attempt, capacity *= 0.75) {
    out.pages = spread_over_pages(texels, capacity, options.max_pages);
    bool crowded = false;
    if (Error e = pack_pages(pp, po, density.scale, out, crowded, scale_kept); e.failed()) return e;
    if (!crowded || attempt >= 3 || out.pages.size() >= std::min<size_t>(options.max_pages, texels.size()))
      break;
  }
  if (out.capped && density.reference > 0) ar.density_factor = density.factor * scale_kept;
  return {};
}

Error write_streams(ImplicitPlan& plan, const AtlasGroup& group, const EncodeOptions& options,
                    GroupAtlas& out) {
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    UvMap& map = out.maps[k];
    map.tau = static_cast<float>(options.tau);
    std::vector<uint8_t> bytes;
    if (const UvStatus st = write_uvmap(map, ip.tri, bytes); st != UvStatus::ok)
      return {ErrorCode::internal, std::string("cannot write the UV bitstream: ") + to_string(st)};
    out.bitstreams.push_back(std::move(bytes));
  }
  // The UVs exactly as the decoder will rebuild them.
  if (Error e = follow_streams(plan, group, out); e.failed()) return e;
  out.patch_texels.assign(out.patch_count, 0.0);
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    const UvMap& map = out.maps[k];
    for (size_t f = 0; f < ip.patch_of_face.size(); ++f) {
      // A copy on its original's texels adds none (texel reuse).
      const uint32_t p = ip.patch_of_face[f];
      if (is_texel_copy(ip, map, p)) continue;
      const double s = placement_scale(map, map.placements[p]);
      out.patch_texels[out.group_patch[k][f]] += layout_face_area(ip.corner_xy, f) * s * s;
    }
  }
  return {};
}

Error follow_streams(ImplicitPlan& plan, const AtlasGroup& group, const GroupAtlas& built) {
  if (built.bitstreams.size() != group.members.size())
    return {ErrorCode::internal, "the atlas holds no bitstream for every member"};
  for (size_t k = 0; k < group.members.size(); ++k) {
    auto& ip = plan.prims[group.members[k]];
    if (const UvStatus st = decode_uvs(ip.tri, built.bitstreams[k], ip.corner_uv); st != UvStatus::ok)
      return {ErrorCode::internal, std::string("the UV bitstream does not decode: ") + to_string(st)};
  }
  return {};
}

}  // namespace gltfwarp
