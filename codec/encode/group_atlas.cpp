// A group's atlas: the stages of group_atlas.h, in order.
#include "codec/encode/group_atlas.h"

#include <cmath>

#include "codec/core/parallel.h"
#include "codec/encode/texture/image_io.h"

namespace gltfwarp {
namespace {

// The stages a full build and a measuring round share: patch numbers,
// density, packing (with the round's effort) and the bitstreams.
Error lay_out_group(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                    const EncodeOptions& options, double density_factor, const StepBias& step_bias,
                    PackEffort effort, GroupAtlas& out) {
  out = GroupAtlas{};
  number_patches(plan, group, out);
  const GroupDensity density = choose_density(model, plan, group, options, density_factor);
  if (Error e = pack_group(plan, group, options, density, step_bias, effort, out); e.failed()) return e;
  return write_streams(plan, group, options, out);
}

}  // namespace

Error build_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                        const EncodeOptions& options, SourceImages& sources, double density_factor,
                        const StepBias& step_bias, GroupAtlas& out, double code_floor) {
  if (Error e =
          lay_out_group(model, plan, group, options, density_factor, step_bias, PackEffort::tightest, out);
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
      if (!warp_page_image(model, plan, group, out, source, coding, *decoded, page, atlas, uvs, err, &wr))
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
                          const StepBias& step_bias, GroupAtlas& out) {
  if (Error e =
          lay_out_group(model, plan, group, options, density_factor, step_bias, PackEffort::one_order, out);
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
      if (!warp_page_image(model, plan, group, out, source, coding, *decoded, page, atlas, uvs, err))
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
    built.report.mip_psnr[l] = built.mip.level[l].values ? built.mip.level[l].psnr() : 0;
    built.report.worst_psnr[l] = built.mip.worst_psnr[l];
  }
  return {};
}

}  // namespace gltfwarp
