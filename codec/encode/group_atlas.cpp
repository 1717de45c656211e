// A group's atlas: the stages of group_atlas.h, in order.
#include "codec/encode/group_atlas.h"

#include "codec/encode/texture/image_io.h"

namespace gltfwarp {

std::string build_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                              const EncodeOptions& options, SourceImages& sources, double density_factor,
                              const StepBias& step_bias, GroupAtlas& out) {
  out = GroupAtlas{};
  number_patches(plan, group, out);
  const GroupDensity density = choose_density(model, plan, group, options, density_factor);
  if (std::string err = pack_group(plan, group, options, density, step_bias, PackEffort::tightest, out);
      !err.empty())
    return err;
  if (std::string err = write_streams(plan, group, options, out); !err.empty()) return err;
  for (const SlotSource& source : slot_sources(model, group)) {
    SourceImage* decoded = nullptr;
    if (std::string err = decode_source(model, source.image, sources, decoded); !err.empty()) return err;
    const SlotCoding coding = slot_coding(model, source, options);
    out.report.source_image_bytes += model.images[source.image].image.size();
    for (uint32_t page = 0; page < out.pages.size(); ++page) {
      OIIO::ImageBuf atlas;
      std::vector<SurfaceUvs> uvs;
      std::string err;
      if (!warp_page_image(model, plan, group, out, source, coding, decoded->pixels, page, atlas, uvs, err))
        continue;  // no member on this page samples the image
      if (!err.empty()) return err;
      const auto palette = snap_page_image(model, source, coding, options, *decoded, atlas);
      WarpJob job{source.key, source.image, page, {}, coding.mime};
      err = code_page_image(atlas, palette, coding, job.bytes);
      if (!err.empty()) return "image " + std::to_string(source.image) + ": " + err;
      if (!source.slot.normal_map) {
        OIIO::ImageBuf shown;
        if (coding.lossy && !decode_image(job.bytes, shown, err))
          return "image " + std::to_string(source.image) + ": cannot read back the coded atlas: " + err;
        measure_page_image(source, coding, *decoded, coding.lossy ? shown : atlas, uvs, out);
      }
      out.report.atlas_image_bytes += job.bytes.size();
      out.jobs.push_back(std::move(job));
    }
  }
  out.report.psnr = out.floor_psnr();
  return {};
}

std::string measure_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                                const EncodeOptions& options, SourceImages& sources, double density_factor,
                                const StepBias& step_bias, GroupAtlas& out) {
  out = GroupAtlas{};
  number_patches(plan, group, out);
  const GroupDensity density = choose_density(model, plan, group, options, density_factor);
  if (std::string err = pack_group(plan, group, options, density, step_bias, PackEffort::one_order, out);
      !err.empty())
    return err;
  if (std::string err = write_streams(plan, group, options, out); !err.empty()) return err;
  for (const SlotSource& source : slot_sources(model, group)) {
    if (source.slot.normal_map) continue;  // measured on colour slots only
    SourceImage* decoded = nullptr;
    if (std::string err = decode_source(model, source.image, sources, decoded); !err.empty()) return err;
    const SlotCoding coding = slot_coding(model, source, options);
    for (uint32_t page = 0; page < out.pages.size(); ++page) {
      OIIO::ImageBuf atlas;
      std::vector<SurfaceUvs> uvs;
      std::string err;
      if (!warp_page_image(model, plan, group, out, source, coding, decoded->pixels, page, atlas, uvs, err))
        continue;
      if (!err.empty()) return err;
      const auto palette = snap_page_image(model, source, coding, options, *decoded, atlas);
      if (!coding.lossy) {
        measure_page_image(source, coding, *decoded, atlas, uvs, out);
        continue;
      }
      std::vector<uint8_t> bytes;
      OIIO::ImageBuf shown;
      err = code_page_image(atlas, palette, coding, bytes);
      if (err.empty() && !decode_image(bytes, shown, err)) err = "cannot read back the coded atlas: " + err;
      if (!err.empty()) return "image " + std::to_string(source.image) + ": " + err;
      measure_page_image(source, coding, *decoded, shown, uvs, out);
    }
  }
  return {};
}

}  // namespace gltfwarp
