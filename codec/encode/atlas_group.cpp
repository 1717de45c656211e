// The encoder's decisions per atlas group (finish_implicit_uvs): build the
// group's atlas (group_atlas.h: density, packing, bitstreams, warp, coding,
// quality), raise its density to the quality floor, spend the headroom
// above it, then either commit it (bitstreams into the primitives, atlases
// into the materials) or give the group back its explicit UVs.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "codec/core/layout_report.h"
#include "codec/core/parallel.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/explicit_alternative.h"
#include "codec/encode/group_atlas.h"
#include "codec/encode/implicit_uv_encoder.h"
#include "codec/encode/quality_search.h"
#include "codec/encode/texture/image_io.h"
#include "format/gltf/draco_geometry.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_materials.h"

namespace gltfwarp {
namespace {

// The sampler of an atlas made from a texture with sampler `source` (-1:
// none): the source's own, with CLAMP_TO_EDGE on both axes, as the atlas must
// not wrap. The filters stay the author's (a NEAREST_MIPMAP_LINEAR source
// stays so; none stays none, left to the viewer as in the source), so a
// viewer filters both files alike. One per source sampler.
int atlas_sampler(tinygltf::Model& model, int source, std::map<int, int>& made) {
  if (const auto it = made.find(source); it != made.end()) return it->second;
  tinygltf::Sampler s;
  if (source >= 0 && source < static_cast<int>(model.samplers.size())) s = model.samplers[source];
  s.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  s.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(s);
  return made[source] = static_cast<int>(model.samplers.size() - 1);
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

void aligned_uv0_image(const tinygltf::Model& model, const tinygltf::Primitive& prim, uint32_t& width,
                       uint32_t& height) {
  width = height = 0;
  uint32_t w = 0, h = 0;
  for (const auto& s : primitive_uv0_slots(model, prim)) {
    const int image = texture_image(model, s.texture);
    int iw = 0, ih = 0;
    std::string err;
    if (!image_size(model.images[image].image, iw, ih, err) || iw <= 0 || ih <= 0) return;
    const auto& m = s.transform;
    if (m[0] != 1 || m[1] != 0 || m[2] != 0 || m[3] != 0 || m[4] != 1 || m[5] != 0) return;
    if (w != 0 && (uint32_t(iw) != w || uint32_t(ih) != h)) return;
    w = uint32_t(iw), h = uint32_t(ih);
  }
  width = w, height = h;
}

namespace {

// The group's primitives get their bitstreams, its materials the atlases.
void commit_group_atlas(tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                        GroupAtlas& built, EncodeReport& report, std::map<int, int>& clamp_samplers,
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
    tinygltf::Texture tex;
    tex.sampler = atlas_sampler(model, std::get<1>(job.key), clamp_samplers);
    model.textures.push_back(tex);
    set_texture_image(model, static_cast<int>(model.textures.size() - 1),
                      static_cast<int>(model.images.size() - 1));
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
Error restore_explicit_uvs(tinygltf::Model& model, const ImplicitPrimitive& ip, const EncodeOptions& options,
                           std::vector<int>& replaced, PrimitiveReport& pr, const Fallback& why) {
  tinygltf::Primitive& prim = model.meshes[ip.mesh].primitives[ip.primitive];
  PrimitiveGeometry geom;
  pr.geometry_bytes = 0;
  pr.bitstream_bytes = 0;
  pr.patches = 0;
  pr.atlas = -1;
  if (Error e =
          rewrite_explicit(model, prim, ip.source_primitive, options, replaced, geom, pr.geometry_bytes);
      e.failed())
    return e;
  pr.handling = Handling::fallback;
  pr.fallback = why;
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
std::set<int> replaceable_images(const tinygltf::Model& model, const AtlasGroup& group,
                                 const GroupAtlas& built) {
  std::set<int> images;
  for (const WarpJob& job : built.jobs) images.insert(job.image);
  for (int m = 0; m < int(model.materials.size()); ++m) {
    const bool ours = std::find(group.materials.begin(), group.materials.end(), m) != group.materials.end();
    for (const TextureSlot& slot : texture_slots(model, m))
      if (!ours || slot.tex_coord != 0) images.erase(texture_image(model, slot.texture));
  }
  return images;
}

size_t replaceable_source_bytes(const tinygltf::Model& model, const AtlasGroup& group,
                                const GroupAtlas& built) {
  size_t bytes = 0;
  for (int i : replaceable_images(model, group, built)) bytes += model.images[i].image.size();
  return bytes;
}

// QualityWeight::surface_area: each member face's UV area at the group's
// mean UV area per 3D area (SurfaceUvs::face_area_uv), so every measure of
// the group weighs a face by its surface. One ratio for the whole group:
// its members' errors add up, page by page and against explicit UVs.
void weigh_faces_by_area(ImplicitPlan& plan, const AtlasGroup& group) {
  std::vector<std::vector<double>> surfaces;  // per member, per face: its 3D area
  double uv_area = 0, surface = 0;
  for (size_t m : group.members) {
    const ImplicitPrimitive& ip = plan.prims[m];
    std::vector<double>& faces = surfaces.emplace_back(ip.tri.face_count());
    for (uint32_t f = 0; f < ip.tri.face_count(); ++f) {
      uv_area += face_area_texels(ip.source_uv, f, 1, 1);
      surface += faces[f] = face_area3(ip.tri, f);
    }
  }
  if (!(surface > 0) || !(uv_area > 0)) return;  // nothing to weigh by: per texel
  const double uv_per_area = uv_area / surface;
  for (size_t k = 0; k < group.members.size(); ++k) {
    std::vector<float>& weights = plan.prims[group.members[k]].face_area_uv;
    weights.resize(surfaces[k].size());
    for (size_t f = 0; f < weights.size(); ++f) weights[f] = float(uv_per_area * surfaces[k][f]);
  }
}

// Every patch of every member `step` scale steps off the packer's choice.
StepBias uniform_step_bias(const ImplicitPlan& plan, const AtlasGroup& group, int32_t step) {
  StepBias bias(group.members.size());
  for (size_t k = 0; k < group.members.size(); ++k)
    bias[k].assign(plan.prims[group.members[k]].patch_count, step);
  return bias;
}

// The quality a group's density aims at (quality_aim).
struct QualityAim {
  double goal = 0;      // dB
  bool boost = false;   // raise the density (density_boosts) until the goal, not only to the floor
  bool strict = false;  // never halve texels below the goal, even while the images outweigh their sources
};
constexpr double kTransparentPsnr = 44.0, kLossyGoalPsnr = 40.0;

// Smooth content keeps its quality with fewer texels. Each round measures
// every patch at two scale steps less than now (half its texels), then
// gives the smaller scale to the patches that buy the most texels for the
// least added error, while the group's error stays under the floor (plus
// half a dB of margin), and while the images are already no larger than
// their sources, above the quality goal too (or where it is, if below). A
// round's result is kept only if its own measurement holds the floor (and
// a target the user set: "never halved below it") and its images are
// smaller; a round below them is tried again with fewer patches halved,
// else the previous atlas stays (the plan's UVs are decoded
// back from its bitstreams, follow_streams) and the search stops.
Error spend_quality_headroom(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                             const EncodeOptions& options, SourceImages& sources, double factor,
                             double min_psnr, const QualityAim& aim, GroupAtlas& built, LayoutMemo* memo) {
  constexpr int32_t kStep = -2;
  StepBias bias = uniform_step_bias(plan, group, 0);
  const size_t source_bytes = replaceable_source_bytes(model, group, built);
  bool plan_follows_built = true;  // the plan's UVs are those of the last build
  for (int round = 0; round < options.adaptive_rounds; ++round) {
    // Images already within their sources' bytes (always, with a strict
    // aim) give up no quality below the goal: an atlas under it stays as it
    // is, one above it goes no lower.
    double target = min_psnr + 0.5;
    if (aim.strict || built.report.atlas_image_bytes <= source_bytes)
      target = std::max(target, std::min(aim.goal, built.error.psnr()));
    // What the round's own measurement must keep: a target the user set
    // (strict) is a promise, so the round may not land below it. The
    // default lossy aim only shapes the budget: holding it there turned the
    // corpus's low JPEG points into explicit-UV files (bench at 2f51dc5: the
    // Duck's BD-rate -4.1% -> +0.2%, TwoSidedPlane's -30.8% -> +4.1%).
    const double hold = aim.strict ? std::max(min_psnr, std::min(aim.goal, built.floor_psnr())) : min_psnr;
    const double budget = double(built.error.values) * 255.0 * 255.0 / std::pow(10.0, target / 10.0);
    StepBias all_down = bias;
    for (auto& b : all_down)
      for (int32_t& step : b) step += kStep;
    GroupAtlas down;
    if (Error e = measure_group_atlas(model, plan, group, options, sources, factor, all_down, down, memo);
        e.failed())
      return e;
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
    size_t taken = 0;
    for (const Choice& c : choices) {
      if (squared + c.added > budget) break;
      squared += c.added;
      ++taken;
    }
    // The per-patch errors predict the round's well where the coder is
    // lossless; a lossy coder's loss does not add up patch by patch, so a
    // round can land below `hold`. Then half as many patches are halved,
    // twice at most, before the search stops.
    bool kept = false;
    for (int attempt = 0; attempt < 3 && taken > 0 && !kept; ++attempt, taken /= 2) {
      std::vector<uint8_t> lower(built.patch_count, 0);
      for (size_t i = 0; i < taken; ++i) lower[choices[i].patch] = 1;
      StepBias next = bias;
      for (size_t k = 0, offset = 0; k < next.size(); ++k) {
        for (size_t p = 0; p < next[k].size(); ++p)
          if (lower[offset + p]) next[k][p] += kStep;
        offset += next[k].size();
      }
      GroupAtlas chosen;
      if (Error e = build_group_atlas(model, plan, group, options, sources, factor, next, chosen, 0, memo);
          e.failed())
        return e;
      // Fewer texels usually mean fewer bytes, but not always (a blurred sharp
      // checker compresses worse): keep a round only if the bytes fell too.
      if (chosen.error.values == 0 || chosen.capped ||
          chosen.report.atlas_image_bytes >= built.report.atlas_image_bytes)
        break;
      if (chosen.floor_psnr() < hold) continue;
      built = std::move(chosen);
      bias = std::move(next);
      plan_follows_built = true;
      kept = true;
    }
    if (kept) continue;
    // Back to the last kept atlas: the plan's UVs follow the last build.
    return follow_streams(plan, group, built);
  }
  // The last build may have been a measurement: the plan's UVs must be built's.
  return plan_follows_built ? Error() : follow_streams(plan, group, built);
}

// The group's atlas at the first density factor, then at each later one
// while it stays below the quality floor (and more density can still help).
Error build_to_floor(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                     const EncodeOptions& options, SourceImages& sources, const std::vector<double>& factors,
                     double min_psnr, const QualityAim& aim, GroupAtlas& built, double& factor_used,
                     LayoutMemo* memo) {
  const double reach = aim.boost ? std::max(min_psnr, aim.goal) : min_psnr;
  // Below the floor the atlas is tried again or given up, never written.
  const double code_floor = options.quality_fallback ? min_psnr : 0;
  for (size_t i = 0; i < factors.size(); ++i) {
    // Below the reach a later factor replaces this atlas, unless it was
    // capped: its lossless pages are coded only if it stays (level-9 PNG of
    // the truck's boosted pages is about a second each).
    const bool last = i + 1 == factors.size();
    const double floor_here = !last && min_psnr > 0 ? std::max(code_floor, reach) : code_floor;
    if (Error e =
            build_group_atlas(model, plan, group, options, sources, factors[i], {}, built, floor_here, memo);
        e.failed())
      return e;
    factor_used = factors[i];
    if (!(min_psnr > 0) || built.error.values == 0 || built.floor_psnr() >= reach || built.capped) {
      // Stopped on an uncoded atlas that the caller may write: build it
      // again with its pages coded (the same atlas: a build is deterministic).
      if (!built.coded && !(built.floor_psnr() < code_floor))
        return build_group_atlas(model, plan, group, options, sources, factors[i], {}, built, code_floor,
                                 memo);
      break;
    }
  }
  return {};
}

// Whether the group's atlas codes a colour slot with a lossy coder (JPEG or
// WebP): the quality aim and rate control both turn on it.
bool codes_colour_lossily(const tinygltf::Model& model, const AtlasGroup& group,
                          const EncodeOptions& options) {
  for (const SlotSource& source : slot_sources(model, group))
    if (slot_coding(model, source, options).lossy) return true;
  return false;
}

// The group's atlas at one coder setting: built up to the floor (and the
// aim), then its headroom above the floor spent on fewer texels. With a
// memo, layouts built before (at another coder setting) are taken from it.
Error build_adapted(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                    const EncodeOptions& options, SourceImages& sources, const std::vector<double>& factors,
                    double min_psnr, const QualityAim& aim, GroupAtlas& built, LayoutMemo* memo = nullptr) {
  double factor_used = factors[0];
  if (Error e = build_to_floor(model, plan, group, options, sources, factors, min_psnr, aim, built,
                               factor_used, memo);
      e.failed())
    return e;
  if (min_psnr > 0 && options.adaptive_density && built.error.values > 0 && !built.capped &&
      built.floor_psnr() >= min_psnr + 0.5)
    return spend_quality_headroom(model, plan, group, options, sources, factor_used, min_psnr, aim, built,
                                  memo);
  return {};
}

// Rate control runs where the user set a target (--target-psnr or
// --quality) but no coder quality, and the group codes a colour slot lossily
// (JPEG or WebP): then the quality is the encoder's to choose.
bool rate_controlled(const tinygltf::Model& model, const AtlasGroup& group, const EncodeOptions& options) {
  return options.goal_psnr > 0 && options.image_quality <= 0 && codes_colour_lossily(model, group, options);
}

// The coder quality (quality_search.h) whose adapted atlas reaches the aim
// (and the floor) with the fewest image bytes: `built` is that atlas, the
// plan's UVs follow it, and `quality` is set. The lossless coder (PNG) runs
// as one more candidate: on flat, few-coloured content its atlas can reach a
// high target in fewer bytes than any JPEG quality (the Duck at 44 dB: a
// 9.9 KB PNG atlas against 14.9 KB at the best JPEG quality, q75, which also
// made explicit UVs look cheaper). It is written where it reaches the target and
// is smaller; `quality` stays the lossy search's, for the sources of a group
// that keeps explicit UVs. `done` hears the share of the work done so far
// (probes, runs and the lossless one), for the progress display.
Error choose_image_quality(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                           const EncodeOptions& options, SourceImages& sources,
                           const std::vector<double>& factors, double min_psnr, const QualityAim& aim,
                           GroupAtlas& built, int& quality, const std::function<void(double)>& done) {
  // Progress: the probes weigh a tenth of a run each (a coder pass on
  // layouts kept), then the runs and the lossless candidate.
  constexpr double kProbeWeight = 0.1;
  constexpr double kWork = kMaxQualityProbes * kProbeWeight + kMaxAdaptedRuns + 1;
  double work = 0;
  std::map<int, GroupAtlas> atlases;  // by quality: the chosen one is kept, not built again
  // The cheapest reaching layout of all probes (the search may write it,
  // QualityChoice::from_probe) and its quality: on a tie the lower quality,
  // as the search picks its cheapest probe.
  GroupAtlas probe_atlas;
  int probe_quality = 0;
  LayoutMemo memo;  // the layouts every quality starts from, built once
  LayoutMemo* const kept = options.layout_memo ? &memo : nullptr;
  const double target = std::max(aim.goal, min_psnr);
  // What build_adapted may do at a quality: raise the density through
  // `factors`, and then (adaptive) halve texels below the factor reached.
  const bool halves = min_psnr > 0 && options.adaptive_density;
  auto probe = [&](int q, QualityProbe& out) -> Error {
    EncodeOptions o = options;
    o.image_quality = q;
    out = {};
    // One uniform layout at the quality: `reached` says whether it reaches.
    auto try_layout = [&](double factor, int32_t step, bool& reached) -> Error {
      // No bias at step 0: the layout build_to_floor makes (and memoises).
      const StepBias bias = step != 0 ? uniform_step_bias(plan, group, step) : StepBias{};
      GroupAtlas atlas;
      if (Error e = build_group_atlas(model, plan, group, o, sources, factor, bias, atlas, 0, kept);
          e.failed())
        return e;
      const double psnr = atlas.error.values > 0 ? atlas.floor_psnr() : 0;
      reached = psnr >= target;
      const size_t bytes = atlas.report.atlas_image_bytes;
      if (reached && (!out.reached || bytes < out.trial.bytes)) out = {true, {bytes, psnr}};
      const size_t kept_bytes = probe_atlas.report.atlas_image_bytes;
      if (reached &&
          (probe_quality == 0 || bytes < kept_bytes || (bytes == kept_bytes && q < probe_quality))) {
        probe_atlas = std::move(atlas);
        probe_quality = q;
      }
      if (!out.reached) out.trial.psnr = std::max(out.trial.psnr, psnr);
      return {};
    };
    // Up the density factors to the first that reaches, as build_to_floor
    // goes, then fewer texels, a scale step at a time, while they still reach.
    bool reached = false;
    size_t i = 0;
    for (; i < factors.size() && !reached; ++i)
      if (Error e = try_layout(factors[i], 0, reached); e.failed()) return e;
    constexpr int32_t kLowestStep = -8;  // a quarter of the texels per side
    for (int32_t step = -1; halves && reached && step >= kLowestStep; --step)
      if (Error e = try_layout(factors[i - 1], step, reached); e.failed()) return e;
    done((work += kProbeWeight) / kWork);
    return {};
  };
  auto run = [&](int q, QualityTrial& trial) -> Error {
    EncodeOptions o = options;
    o.image_quality = q;
    GroupAtlas& atlas = atlases[q];
    if (Error e = build_adapted(model, plan, group, o, sources, factors, min_psnr, aim, atlas, kept);
        e.failed())
      return e;
    trial.bytes = atlas.report.atlas_image_bytes;
    trial.psnr = atlas.error.values > 0 ? atlas.floor_psnr() : 0;
    done((work += 1) / kWork);
    return {};
  };
  QualityChoice choice;
  if (Error e = search_image_quality(target, probe, run, choice); e.failed()) return e;
  if (choice.from_probe && choice.quality != probe_quality)
    return {ErrorCode::internal, "rate control chose a probe's layout it did not keep"};
  built = std::move(choice.from_probe ? probe_atlas : atlases[choice.quality]);
  built.report.image_quality = choice.quality;
  built.report.quality_trials = choice.trials;
  built.report.quality_probes = choice.probes;
  built.report.quality_reached = choice.reached;
  built.report.quality_uniform = choice.from_probe;
  quality = choice.quality;
  // Where every source is a PNG, as --image-format keep writes them: a
  // source's palette then stays the atlas's (snap_page_image).
  EncodeOptions lossless = options;
  lossless.image_format = "keep";
  for (const SlotSource& source : slot_sources(model, group))
    if (output_mime(model.images[size_t(source.image)].image, "keep") != "image/png")
      lossless.image_format = "png";
  GroupAtlas png;
  if (Error e = build_adapted(model, plan, group, lossless, sources, factors, min_psnr, aim, png); e.failed())
    return e;
  done(1.0);
  const bool png_reaches = png.error.values > 0 && png.floor_psnr() >= target;
  if (png_reaches && (!choice.reached || png.report.atlas_image_bytes < built.report.atlas_image_bytes)) {
    png.report.lossless_chosen = true;
    png.report.lossy_quality_beaten = choice.quality;
    png.report.lossy_bytes_beaten = built.report.atlas_image_bytes;
    png.report.quality_trials = choice.trials + 1;
    png.report.quality_probes = choice.probes;
    png.report.quality_reached = true;
    built = std::move(png);
  }
  return follow_streams(plan, group, built);
}

// The lossy-coded sources (lossy_sources' keys).
std::set<int> images_of(const LossySources& lossy) {
  std::set<int> images;
  for (const auto& entry : lossy) images.insert(entry.first);
  return images;
}

// Under a target the user asked for a quality, not a coder setting: a
// group that keeps explicit UVs writes each colour source of `searched`
// (targeted_sources) in the smallest form (quality, size) whose surface PSNR
// reaches it, as equal_quality_images at that target finds it (`priced`,
// where the caller searched at that target already), and leaves out of
// `recode` (so as it is) a source that no form brings there in fewer bytes
// than it has, counting the lossy-coded ones (a lossless one as it was is
// no news); `forms` gets the forms found. A group below the floor wrote its
// sources at the closest trial's quality instead (often q95), whatever the
// target, and one whose chosen atlas fell short of the target wrote them
// short of it too. Both fallbacks (below the floor, explicit smaller) come here.
Error sources_for_target(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                         const GroupAtlas& built, const LossySources& searched,
                         const LosslessRepacks& repacks, const NormalMapsAsAsked& normals, double target,
                         const EqualQualityImages* priced, SourceImages& sources, LossySources& recode,
                         SourceForms& forms, Fallback& why) {
  EqualQualityImages found_at_target;
  if (!priced) {
    if (Error e = equal_quality_images(model, plan, group, built, sources, images_of(searched), searched,
                                       repacks, normals, target, true, found_at_target);
        e.failed())
      return e;
  }
  const EqualQualityImages& at_target = priced ? *priced : found_at_target;
  recode.clear();
  forms = at_target.forms;
  why.target_psnr = target;
  for (const auto& [image, source_coding] : searched) {
    const auto found = at_target.qualities.find(image);
    if (found == at_target.qualities.end() && !source_coding.second.lossy) continue;  // lossless, as it was
    if (found == at_target.qualities.end()) {
      ++why.images_kept_for_target;
      const auto repacked = repacks.find(image);
      why.kept_for_target_bytes +=
          repacked != repacks.end() ? repacked->second.size() : model.images[size_t(image)].image.size();
      why.explicit_image_mime = source_coding.second.mime;
      continue;
    }
    recode.emplace(image, source_coding).first->second.second.quality = found->second;
  }
  return {};
}

// A group that keeps explicit UVs writes its source images as the
// comparison priced them: colour sources in the coder asked (or, under a
// target, in the form and quality that reach it: a source kept under
// --image-format keep too, PNG or JPEG), the others re-coded losslessly where
// that is smaller (PNGs, JPEGs' entropy code), normal maps in the coder
// asked. Both fallbacks (below the floor, explicit smaller) end so.
Error write_kept_sources(tinygltf::Model& model, const EncodeOptions& options, bool targeted,
                         const LossySources& recode, const SourceForms& forms, const LosslessRepacks& repacks,
                         const NormalMapsAsAsked& normals, SourceImages& sources, Fallback& why) {
  LosslessRepacks unless_recoded = repacks;
  if (targeted || options.image_format == "jpeg" || options.image_format == "webp")
    if (Error e = recode_sources_as_asked(model, recode, forms, sources, unless_recoded, why); e.failed())
      return e;
  write_lossless_repacks(model, unless_recoded, why);
  write_normal_maps_as_asked(model, normals, why);
  return {};
}

// What the group's density aims at (EncodeOptions::goal_psnr): by default
// 44 dB, near transparency, where the colour slots are coded losslessly, and
// boosted up to it; a lossy coder's own loss caps the quality, so there
// the goal stays 40 dB and only bounds the halving while the images are
// smaller than their sources.
QualityAim quality_aim(const tinygltf::Model& model, const AtlasGroup& group, const EncodeOptions& options) {
  if (options.goal_psnr == 0) return {0, false, false};
  if (options.goal_psnr > 0) return {options.goal_psnr, true, true};
  if (codes_colour_lossily(model, group, options)) return {kLossyGoalPsnr, false, false};
  return {kTransparentPsnr, true, true};
}

}  // namespace

Error finish_implicit_uvs(tinygltf::Model& model, ImplicitPlan& plan, const EncodeOptions& options,
                          std::vector<int>& replaced, EncodeReport& report) {
  plan.seam_textures.clear();  // the partitions are made
  plan.seam_materials.clear();
  std::map<int, int> clamp_samplers;  // source sampler -> its atlas copy
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
  auto keep_explicit = [&](const AtlasGroup& group, const Fallback& why) -> Error {
    for (size_t m : group.members) {
      auto& pr = report.primitives[plan.prims[m].report_index];
      if (Error e = restore_explicit_uvs(model, plan.prims[m], options, replaced, pr, why); e.failed())
        return e;
      Note note;
      note.kind = NoteKind::fallback;
      note.mesh = pr.mesh;
      note.primitive = pr.primitive;
      note.fallback = why;
      report.notes.push_back(note);
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
    if (options.quality_weight == QualityWeight::surface_area) weigh_faces_by_area(plan, group);
    const QualityAim aim = quality_aim(model, group, options);
    // The options this group is written with: the coder quality rate
    // control chose, where it ran.
    EncodeOptions group_options = options;
    const bool controlled = rate_controlled(model, group, options);
    // A target and no coder quality: a group that keeps explicit UVs writes
    // its colour sources in the smallest form that reaches it, fewer texels
    // included, with a lossless coder too (explicit_alternative.h).
    const bool targeted = options.goal_psnr > 0 && options.image_quality <= 0;
    if (controlled) {
      // Rate control runs up to ten atlas pipelines: the trials move the bar.
      const auto trials_done = [&](double share) {
        if (options.progress) options.progress("atlas", (double(gi) + share) / double(plan.groups.size()));
      };
      if (Error e = choose_image_quality(model, plan, group, options, sources, factors, min_psnr, aim, built,
                                         group_options.image_quality, trials_done);
          e.failed())
        return e;
    } else if (Error e = build_adapted(model, plan, group, options, sources, factors, min_psnr, aim, built);
               e.failed()) {
      return e;
    }
    const double psnr = built.floor_psnr();
    if (min_psnr > 0 && built.error.values > 0 && psnr < min_psnr && options.quality_fallback) {
      Fallback why;
      why.reason = FallbackReason::below_quality_floor;
      why.psnr = psnr;
      why.density_factor = built.report.density_factor;
      why.capped = built.capped;
      why.min_psnr = min_psnr;
      // Asked for JPEG q10, the user gets JPEG q10 sources, not the PNG
      // they gave (TwoSidedPlane: 157,852 B at 99 dB kept for a q10 encode).
      const std::set<int> replaceable = replaceable_images(model, group, built);
      LossySources lossy = lossy_sources(model, group, group_options, replaceable);
      LosslessRepacks repacks;
      if (Error e = lossless_repacks(model, replaceable, lossy, sources, repacks); e.failed()) return e;
      NormalMapsAsAsked normals;
      if (Error e = normal_maps_as_asked(model, group, group_options, replaceable, lossy, sources, repacks,
                                         normals);
          e.failed())
        return e;
      SourceForms forms;
      if (targeted)
        if (Error e = sources_for_target(
                model, plan, group, built, targeted_sources(model, group, group_options, replaceable),
                repacks, normals, std::max(aim.goal, min_psnr), nullptr, sources, lossy, forms, why);
            e.failed())
          return e;
      if (Error e = write_kept_sources(model, group_options, targeted, lossy, forms, repacks, normals,
                                       sources, why);
          e.failed())
        return e;
      if (Error e = keep_explicit(group, why); e.failed()) return e;
      continue;
    }
    // The method exists to save bytes at equal quality: when explicit UVs
    // with the source images at the atlas's quality (explicit_alternative.h)
    // cost no more than the map and the atlas, keep the explicit UVs. The
    // figures go in the report either way.
    size_t implicit_bytes = built.report.atlas_image_bytes, explicit_bytes = 0;
    // A Draco encode per member (about a second for each part of a 1M-face
    // mesh): side by side.
    std::vector<size_t> member_explicit(group.members.size(), 0);
    run_in_parallel(group.members.size(), worker_count(group.members.size()), [&](size_t k, size_t) {
      member_explicit[k] = explicit_geometry_bytes(model, plan.prims[group.members[k]], options);
    });
    for (size_t k = 0; k < group.members.size(); ++k) {
      const ImplicitPrimitive& ip = plan.prims[group.members[k]];
      implicit_bytes += report.primitives[ip.report_index].geometry_bytes + built.bitstreams[k].size();
      explicit_bytes += member_explicit[k];
    }
    EqualQualityImages alternative;
    const std::set<int> replaceable = replaceable_images(model, group, built);
    const LossySources lossy = lossy_sources(model, group, group_options, replaceable);
    // Only a group that may fall back needs them (PNG coding of a large
    // atlas-sized source costs seconds); with --always-implicit the report
    // prices the sources as they are.
    LosslessRepacks repacks;
    if (options.quality_fallback)
      if (Error e = lossless_repacks(model, replaceable, lossy, sources, repacks); e.failed()) return e;
    NormalMapsAsAsked normals;
    if (Error e =
            normal_maps_as_asked(model, group, group_options, replaceable, lossy, sources, repacks, normals);
        e.failed())
      return e;
    // Under a target the explicit file may have fewer texels too, as it
    // will be written (try_downscales), PNG sources included.
    const LossySources searched =
        targeted ? targeted_sources(model, group, group_options, replaceable) : lossy;
    if (Error e = equal_quality_images(model, plan, group, built, sources, replaceable, searched, repacks,
                                       normals, built.floor_psnr(), targeted, alternative);
        e.failed())
      return e;
    explicit_bytes += alternative.bytes;
    built.report.file_bytes = implicit_bytes;
    built.report.explicit_bytes = explicit_bytes;
    built.report.explicit_psnr = alternative.psnr;
    built.report.explicit_image_quality = alternative.quality;
    built.report.explicit_image_mime = alternative.mime;
    if (options.quality_fallback && implicit_bytes > explicit_bytes) {
      Fallback why;
      why.reason = FallbackReason::explicit_smaller;
      why.explicit_bytes = explicit_bytes;
      why.implicit_bytes = implicit_bytes;
      why.psnr = built.floor_psnr();
      why.explicit_psnr = alternative.psnr;
      why.explicit_image_quality = alternative.quality;
      why.explicit_image_mime = alternative.mime;
      // Under rate control each source goes out at the quality that reaches
      // both the atlas's (the file the comparison priced) and the target.
      // The comparison searched them at the atlas's quality already: only a
      // higher target needs a second search.
      LossySources recode = lossy;
      SourceForms forms;
      if (targeted) {
        // A lossless atlas has no coder quality to stop at the target, so
        // its overshoot (40.7 dB for 40) is not a quality the user asked
        // for: the sources then go out at the target itself, fewer bytes
        // than the comparison priced.
        const double target =
            built.report.lossless_chosen ? aim.goal : std::max(built.floor_psnr(), aim.goal);
        const EqualQualityImages* priced = target != built.floor_psnr() ? nullptr : &alternative;
        if (Error e = sources_for_target(model, plan, group, built, searched, repacks, normals, target,
                                         priced, sources, recode, forms, why);
            e.failed())
          return e;
      }
      if (Error e = write_kept_sources(model, group_options, targeted, recode, forms, repacks, normals,
                                       sources, why);
          e.failed())
        return e;
      if (Error e = keep_explicit(group, why); e.failed()) return e;
      continue;
    }
    if (!built.coded) return {ErrorCode::internal, "an atlas below the quality floor was not coded"};
    if (Error e = measure_mip_levels(model, plan, group, group_options, sources, built); e.failed()) return e;
    commit_group_atlas(model, plan, group, built, report, clamp_samplers, retired_textures);
  }
  drop_unused_textures(model, retired_textures);
  if (options.progress) options.progress("atlas", 1.0);
  return {};
}

}  // namespace gltfwarp
