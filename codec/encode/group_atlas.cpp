// A group's atlas: the stages of group_atlas.h, in order.
#include "codec/encode/group_atlas.h"

#include <cmath>
#include <cstring>

#include "codec/core/parallel.h"
#include "codec/encode/texture/image_io.h"

namespace gltfwarp {
namespace {

// The stages a full build and a measuring round share: patch numbers,
// density, packing (with the round's effort) and the bitstreams. With a
// memo, `kept` is the layout's entry there (null: not kept), and a layout
// built before is copied from it, the plan's UVs decoded from its streams.
Error lay_out_group(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                    const EncodeOptions& options, double density_factor, const StepBias& step_bias,
                    PackEffort effort, GroupAtlas& out, LayoutMemo* memo, LayoutMemo::Entry*& kept) {
  bool found = false;
  kept =
      memo ? memo->find_or_add(density_factor, step_bias, int(effort), options.image_format, found) : nullptr;
  if (found) {
    out = kept->layout;
    return follow_streams(plan, group, out);
  }
  out = GroupAtlas{};
  number_patches(plan, group, out);
  const GroupDensity density = choose_density(model, plan, group, options, density_factor);
  if (Error e = pack_group(plan, group, options, density, step_bias, effort, out); e.failed()) return e;
  if (Error e = write_streams(plan, group, options, out); e.failed()) return e;
  if (kept) {
    kept->layout = out;
    kept->filled = true;
  }
  return {};
}

}  // namespace

LayoutMemo::Entry* LayoutMemo::find_or_add(double density_factor, const StepBias& step_bias, int effort,
                                           const std::string& image_format, bool& found) {
  found = false;
  int32_t step = 0;
  bool first = true;
  for (const auto& member : step_bias)
    for (int32_t s : member) {
      if (first) {
        step = s, first = false;
      } else if (s != step) {
        return nullptr;  // a round's own choice: no other quality builds it
      }
    }
  uint64_t factor_bits = 0;
  std::memcpy(&factor_bits, &density_factor, sizeof factor_bits);
  auto [it, fresh] = entries.try_emplace({factor_bits, step_bias.empty(), step, effort, image_format});
  if (fresh) {
    it->second = std::make_unique<Entry>();
    it->second->memo = this;
  }
  found = it->second->filled;
  return it->second.get();
}

bool LayoutMemo::Entry::take(const JobKey& key, uint32_t page, OIIO::ImageBuf& atlas,
                             WarpReport* report) const {
  const auto it = pages.find({key, page});
  if (it == pages.end()) return false;
  atlas.copy(it->second.atlas);
  if (report) {
    *report = it->second.report;
    report->seconds = report->fit_seconds = 0;  // a copy is no warp's time
  }
  return true;
}

void LayoutMemo::Entry::keep(const JobKey& key, uint32_t page, const OIIO::ImageBuf& atlas,
                             const WarpReport& report) {
  const size_t bytes = atlas.spec().image_bytes();
  if (memo->warped_bytes + bytes > kMaxWarpedBytes || pages.count({key, page})) return;
  Page& kept = pages[{key, page}];
  kept.atlas.copy(atlas);
  kept.report = report;
  memo->warped_bytes += bytes;
}

Error build_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                        const EncodeOptions& options, SourceImages& sources, double density_factor,
                        const StepBias& step_bias, GroupAtlas& out, double code_floor, LayoutMemo* memo) {
  LayoutMemo::Entry* kept = nullptr;
  if (Error e = lay_out_group(model, plan, group, options, density_factor, step_bias, PackEffort::tightest,
                              out, memo, kept);
      e.failed())
    return e;
  // Lossless pages are measured before they are coded (the coding does not
  // change what a viewer shows), so an atlas below `code_floor`, which the
  // caller will not keep, is never coded: level-9 PNG of atlas-sized pages
  // is a fifth of the 1M-face sample's encode. The pages kept are coded
  // together at the end, side by side (a page's two PNG passes are unequal,
  // so one page alone keeps about one core busy). Held up to a bound on memory.
  struct Uncoded {
    size_t job;
    OIIO::ImageBuf atlas;
    std::span<const PaletteEntry> palette;
    SlotCoding coding;
  };
  std::vector<Uncoded> uncoded;
  size_t held_bytes = 0;
  constexpr size_t kMaxHeldBytes = size_t(1) << 30;
  for (const SlotSource& source : slot_sources(model, group)) {
    SourceImage* decoded = nullptr;
    if (Error e = decode_source(model, source.image, sources, decoded); e.failed()) return e;
    const SlotCoding coding = slot_coding(model, source, options);
    out.report.source_image_bytes += model.images[source.image].image.size();
    for (uint32_t page = 0; page < out.pages.size(); ++page) {
      OIIO::ImageBuf atlas;
      std::vector<SurfaceUvs> uvs;
      Error err;
      WarpReport wr;
      if (!warp_page_image(model, plan, group, out, source, coding, *decoded, page, atlas, uvs, err, &wr,
                           kept))
        continue;  // no member on this page samples the image
      if (err.failed()) return err;
      if (!source.slot.normal_map) out.fit_before += wr.fit.error_before, out.fit_after += wr.fit.error_after;
      out.report.fit_seconds += wr.fit_seconds;
      const auto palette = snap_page_image(model, source, coding, options, *decoded, atlas);
      WarpJob job{source.key, source.image, page, {}, coding.mime};
      const std::string image = "image " + std::to_string(source.image) + ": ";
      const size_t atlas_bytes = atlas.spec().image_bytes();
      if (!coding.lossy && held_bytes + atlas_bytes <= kMaxHeldBytes) {
        if (!source.slot.normal_map) measure_page_image(source, coding, *decoded, atlas, uvs, out);
        held_bytes += atlas_bytes;
        uncoded.push_back({out.jobs.size(), std::move(atlas), palette, coding});
        out.jobs.push_back(std::move(job));
        continue;
      }
      if (Error e = code_page_image(atlas, palette, coding, job.bytes); e.failed()) return e.at(image);
      if (!source.slot.normal_map) {
        OIIO::ImageBuf shown;
        if (std::string why; coding.lossy && !decode_image(job.bytes, shown, why))
          return {ErrorCode::internal, image + "cannot read back the coded atlas: " + why};
        measure_page_image(source, coding, *decoded, coding.lossy ? shown : atlas, uvs, out);
      }
      out.report.atlas_image_bytes += job.bytes.size();
      out.jobs.push_back(std::move(job));
    }
  }
  out.coded = uncoded.empty() || !(out.error.values > 0 && out.floor_psnr() < code_floor);
  if (out.coded) {
    std::vector<Error> errors(uncoded.size());
    run_in_parallel(uncoded.size(), worker_count(uncoded.size()), [&](size_t i, size_t) {
      errors[i] = code_page_image(uncoded[i].atlas, uncoded[i].palette, uncoded[i].coding,
                                  out.jobs[uncoded[i].job].bytes);
      uncoded[i].atlas.clear();  // the page's pixels are no longer needed
    });
    for (size_t i = 0; i < uncoded.size(); ++i) {
      const WarpJob& job = out.jobs[uncoded[i].job];
      if (errors[i].failed()) return errors[i].at("image " + std::to_string(job.image) + ": ");
      out.report.atlas_image_bytes += job.bytes.size();
    }
  }
  out.report.psnr = out.floor_psnr();
  if (out.fit_before > 0 && out.fit_after > 0)
    out.report.fit_gain_db = 10 * std::log10(out.fit_before / out.fit_after);
  return {};
}

Error measure_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                          const EncodeOptions& options, SourceImages& sources, double density_factor,
                          const StepBias& step_bias, GroupAtlas& out, LayoutMemo* memo) {
  LayoutMemo::Entry* kept = nullptr;
  if (Error e = lay_out_group(model, plan, group, options, density_factor, step_bias, PackEffort::one_order,
                              out, memo, kept);
      e.failed())
    return e;
  for (const SlotSource& source : slot_sources(model, group)) {
    if (source.slot.normal_map) continue;  // measured on colour slots only
    SourceImage* decoded = nullptr;
    if (Error e = decode_source(model, source.image, sources, decoded); e.failed()) return e;
    const SlotCoding coding = slot_coding(model, source, options);
    for (uint32_t page = 0; page < out.pages.size(); ++page) {
      OIIO::ImageBuf atlas;
      std::vector<SurfaceUvs> uvs;
      Error err;
      if (!warp_page_image(model, plan, group, out, source, coding, *decoded, page, atlas, uvs, err, nullptr,
                           kept))
        continue;
      if (err.failed()) return err;
      const auto palette = snap_page_image(model, source, coding, options, *decoded, atlas);
      if (!coding.lossy) {
        measure_page_image(source, coding, *decoded, atlas, uvs, out);
        continue;
      }
      const std::string image = "image " + std::to_string(source.image) + ": ";
      std::vector<uint8_t> bytes;
      OIIO::ImageBuf shown;
      if (Error e = code_page_image(atlas, palette, coding, bytes); e.failed()) return e.at(image);
      if (std::string why; !decode_image(bytes, shown, why))
        return {ErrorCode::internal, image + "cannot read back the coded atlas: " + why};
      measure_page_image(source, coding, *decoded, shown, uvs, out);
    }
  }
  return {};
}

Error measure_mip_levels(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                         const EncodeOptions& options, SourceImages& sources, GroupAtlas& built) {
  built.mip = {};
  for (const SlotSource& source : slot_sources(model, group)) {
    if (source.slot.normal_map) continue;  // colour slots only, as measure_page_image
    SourceImage* decoded = nullptr;
    if (Error e = decode_source(model, source.image, sources, decoded); e.failed()) return e;
    const SlotCoding coding = slot_coding(model, source, options);
    std::vector<TextureSampler> reference;  // built on the first page, for all of them
    for (const WarpJob& job : built.jobs) {
      if (job.key != source.key) continue;
      const std::vector<SurfaceUvs> uvs = page_surface_uvs(model, plan, group, built, source.image, job.page);
      if (uvs.empty()) continue;
      // What a viewer samples: the page's bytes decoded (for PNG, the texels warped).
      OIIO::ImageBuf shown;
      if (std::string why; !decode_image(job.bytes, shown, why))
        return {ErrorCode::internal,
                "image " + std::to_string(source.image) + ": cannot read back the coded atlas: " + why};
      if (reference.empty()) reference = group_mip_reference(model, plan, group, source, coding, *decoded);
      const MipQuality mq = mip_surface_error(reference, page_sampler(source, shown), uvs);
      if (built.mip.level[0].values == 0)
        built.mip = mq;
      else
        built.mip.add(mq);
    }
  }
  for (size_t l = 0; l < kMipLevels; ++l) {
    built.report.mip_psnr[l] = built.mip.level[l].values != 0 ? built.mip.level[l].psnr() : 0;
    built.report.worst_psnr[l] = built.mip.worst_psnr[l];
  }
  return {};
}

}  // namespace gltfwarp
