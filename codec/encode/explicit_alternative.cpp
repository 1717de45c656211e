// The source images at the atlas's quality, with explicit UVs (see explicit_alternative.h).
#include "codec/encode/explicit_alternative.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <OpenImageIO/imagebufalgo.h>

#include "codec/encode/implicit_uv_encoder.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/jpeg_writer.h"
#include "codec/encode/texture/mip_quality.h"
#include "codec/encode/texture/warp_quality.h"

namespace gltfwarp {
namespace {

constexpr uint64_t kSearchPoints = 1'000'000;  // surface points per measurement (as the atlas's, spread)

// The group's faces that sample `image`: the source at its UVs against the
// re-coded image at the UVs an explicit-UV file carries (Draco-quantized).
// A user's explicit-UV file has that loss too: baseline 1's lossless PNG
// truck measures 48.4 dB, not 99, and pricing it without the loss found
// JPEG q39 at 44.0 dB where `compare` measures the file at 42.6 dB.
std::vector<SurfaceUvs> faces_sampling(const tinygltf::Model& model, const ImplicitPlan& plan,
                                       const AtlasGroup& group, const GroupAtlas& built, int image) {
  std::vector<SurfaceUvs> uvs;
  for (size_t k = 0; k < group.members.size(); ++k) {
    const auto& ip = plan.prims[group.members[k]];
    if (samples_image(model, ip, image))
      uvs.push_back({ip.source_uv, ip.explicit_uv.empty() ? ip.source_uv : ip.explicit_uv,
                     built.group_patch[k], ip.face_area_uv});
  }
  return uvs;
}

struct Coded {
  size_t bytes = 0;
  double psnr = 0;
  MipQuality at_mips;  // against the source's own MIP chain, where asked
};

// `pixels` at `scale` of their size (OIIO's resize, its default filter, on
// the stored values: what baseline 2 of the benchmark does); `pixels`
// themselves at scale 1.
OIIO::ImageBuf scaled(const OIIO::ImageBuf& pixels, double scale) {
  if (scale == 1.0) return pixels;
  const OIIO::ImageSpec& sp = pixels.spec();
  const int w = std::max(1, int(std::lround(sp.width * scale)));
  const int h = std::max(1, int(std::lround(sp.height * scale)));
  return OIIO::ImageBufAlgo::resize(pixels, "", 0, OIIO::ROI(0, w, 0, h, 0, 1, 0, sp.nchannels));
}

// Source image `image`, at `scale` of its size, through the coder and quality of `coding`.
Error code_as(const tinygltf::Model& model, int image, const SlotCoding& coding, double scale,
              SourceImages& sources, std::vector<uint8_t>& bytes) {
  SourceImage* decoded = nullptr;
  if (Error e = decode_source(model, image, sources, decoded); e.failed()) return e;
  std::string err;
  if (!encode_image(scaled(decoded->pixels, scale), coding.mime, coding.quality, bytes, err))
    return {ErrorCode::internal, "image " + std::to_string(image) + ": " + err};
  return {};
}

}  // namespace

namespace {

// The images among `images` shown through a colour slot that `keep` takes,
// each with the first such slot (it decides the coding and sampler).
template <class Keep>
LossySources colour_slots(const tinygltf::Model& model, const AtlasGroup& group, const EncodeOptions& options,
                          const std::set<int>& images, Keep keep) {
  LossySources found;
  for (const SlotSource& source : slot_sources(model, group)) {
    if (!images.count(source.image) || found.count(source.image) || source.slot.normal_map) continue;
    if (SlotCoding coding = slot_coding(model, source, options); keep(coding))
      found.emplace(source.image, std::pair{source, std::move(coding)});
  }
  return found;
}

}  // namespace

LossySources lossy_sources(const tinygltf::Model& model, const AtlasGroup& group,
                           const EncodeOptions& options, const std::set<int>& images) {
  return colour_slots(model, group, options, images, [](const SlotCoding& c) { return c.lossy; });
}

LossySources targeted_sources(const tinygltf::Model& model, const AtlasGroup& group,
                              const EncodeOptions& options, const std::set<int>& images) {
  return colour_slots(model, group, options, images, [](const SlotCoding&) { return true; });
}

Error recode_sources_as_asked(tinygltf::Model& model, const LossySources& lossy, const SourceForms& forms,
                              SourceImages& sources, LosslessRepacks& repacks, Fallback& why) {
  for (const auto& [image, source_coding] : lossy) {
    SlotCoding coding = source_coding.second;
    const auto formed = forms.find(image);
    const SourceForm form = formed != forms.end() ? formed->second : SourceForm{};
    if (form.png) coding.mime = "image/png";
    std::vector<uint8_t> bytes;
    if (Error e = code_as(model, image, coding, form.scale, sources, bytes); e.failed()) return e;
    // The coder asked can only lose quality here: where it does not save
    // bytes either, the source as it is is the better file on both counts
    // (the Fox's flat-colour 26.8 KB PNG: with it as JPEG q85 the file is
    // 153,460 B at 39.5 dB, with the PNG 110,564 B at 52.1 dB; bench at 689e4e2).
    const auto repacked = repacks.find(image);
    const size_t source_bytes =
        repacked != repacks.end() ? repacked->second.size() : model.images[size_t(image)].image.size();
    if (bytes.size() >= source_bytes) {
      ++why.images_kept;
      why.kept_bytes += source_bytes;
      why.kept_recoded_bytes += bytes.size();
      why.kept_recoded_quality = coding.quality;
      why.explicit_image_mime = source_coding.second.mime;
      continue;
    }
    if (repacked != repacks.end()) repacks.erase(repacked);
    replace_image_bytes(model, image, std::move(bytes), coding.mime);
    if (form.scale < 1.0) {
      ++why.images_downscaled;
      why.images_downscaled_png += form.png;
      why.images_scale = why.images_scale > 0 ? std::min(why.images_scale, form.scale) : form.scale;
    }
    if (!form.png) why.images_recoded_quality = std::max(why.images_recoded_quality, coding.quality);
    why.explicit_image_mime = source_coding.second.mime;
  }
  return {};
}

namespace {

// Whether `ours` decodes to exactly `pixels`: lossless by construction, and
// checked, since a file's pixels are at stake.
bool same_pixels(std::span<const uint8_t> ours, const OIIO::ImageBuf& pixels) {
  OIIO::ImageBuf back;
  std::string why;
  if (!decode_image(ours, back, why)) return false;
  const OIIO::ImageSpec &a = back.spec(), &b = pixels.spec();
  if (a.width != b.width || a.height != b.height || a.nchannels != b.nchannels || a.format != b.format)
    return false;
  return OIIO::ImageBufAlgo::compare(back, pixels, 0.0f, 0.0f).maxerror == 0;
}

}  // namespace

Error lossless_repacks(const tinygltf::Model& model, const std::set<int>& images, const LossySources& lossy,
                       SourceImages& sources, LosslessRepacks& out) {
  out.clear();
  for (int image : images) {
    const std::vector<uint8_t>& bytes = model.images[size_t(image)].image;
    const ImageCodec codec = sniff_image_codec(bytes);
    // A JPEG keeps its coefficients, so it qualifies even where the group
    // would code it lossily: kept as it is, it is kept in fewer bytes.
    const bool png = codec == ImageCodec::png && !lossy.count(image) && png_holds_only_pixels(bytes);
    if (!png && codec != ImageCodec::jpeg) continue;
    SourceImage* decoded = nullptr;
    if (Error e = decode_source(model, image, sources, decoded); e.failed()) return e;
    std::vector<uint8_t> ours;
    const std::string why =
        png ? encode_image(decoded->pixels, ImageEncodeOptions{}, ours) : recode_jpeg_losslessly(bytes, ours);
    if (png && !why.empty()) return {ErrorCode::internal, "image " + std::to_string(image) + ": " + why};
    // A JPEG libjpeg cannot re-code (arithmetic-coded, say) stays as it is.
    if (!why.empty() || ours.size() >= bytes.size() || !same_pixels(ours, decoded->pixels)) continue;
    out.emplace(image, std::move(ours));
  }
  return {};
}

void write_lossless_repacks(tinygltf::Model& model, const LosslessRepacks& repacks, Fallback& why) {
  for (const auto& [image, bytes] : repacks) {
    why.repacked_bytes_before += model.images[size_t(image)].image.size();
    why.repacked_bytes_after += bytes.size();
    ++why.images_repacked;
    replace_image_bytes(model, image, bytes,
                        sniff_image_codec(bytes) == ImageCodec::jpeg ? "image/jpeg" : "image/png");
  }
}

Error normal_maps_as_asked(const tinygltf::Model& model, const AtlasGroup& group,
                           const EncodeOptions& options, const std::set<int>& images,
                           const LossySources& lossy, SourceImages& sources, LosslessRepacks& repacks,
                           NormalMapsAsAsked& out) {
  out = {};
  if (options.image_format != "jpeg" && options.image_format != "webp") return {};
  for (const SlotSource& source : slot_sources(model, group)) {
    const int image = source.image;
    if (!source.slot.normal_map || !images.count(image) || lossy.count(image) || out.bytes.count(image))
      continue;
    const SlotCoding coding = slot_coding(model, source, options);
    std::vector<uint8_t> bytes;
    if (Error e = code_as(model, image, coding, 1.0, sources, bytes); e.failed()) return e;
    const auto repacked = repacks.find(image);
    const size_t now =
        repacked != repacks.end() ? repacked->second.size() : model.images[size_t(image)].image.size();
    if (bytes.size() >= now) continue;  // smaller and lossless beats larger and lossy
    if (repacked != repacks.end()) repacks.erase(repacked);
    out.bytes.emplace(image, std::move(bytes));
    out.mime = coding.mime;
    out.quality = std::max(out.quality, coding.quality);
  }
  return {};
}

void write_normal_maps_as_asked(tinygltf::Model& model, const NormalMapsAsAsked& normals, Fallback& why) {
  for (const auto& [image, bytes] : normals.bytes) {
    replace_image_bytes(model, image, bytes, normals.mime);
    ++why.normal_maps_recoded;
  }
  why.normal_maps_quality = normals.quality;
  if (why.explicit_image_mime.empty()) why.explicit_image_mime = normals.mime;
}

Error equal_quality_images(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                           const GroupAtlas& built, SourceImages& sources, const std::set<int>& images,
                           const LossySources& lossy, const LosslessRepacks& repacks,
                           const NormalMapsAsAsked& normals, double target_psnr, bool try_downscales,
                           EqualQualityImages& out) {
  out = {};
  for (int image : images) {
    const auto repacked = repacks.find(image);
    const auto normal = normals.bytes.find(image);
    const size_t as_is = normal != normals.bytes.end() ? normal->second.size()
                         : repacked != repacks.end()   ? repacked->second.size()
                                                       : model.images[size_t(image)].image.size();
    auto it = lossy.find(image);
    if (it == lossy.end() || !(target_psnr > 0)) {
      out.bytes += as_is;
      continue;
    }
    // Named references, not a structured binding: lambdas below capture them.
    const SlotSource& source = it->second.first;
    const SlotCoding& coding = it->second.second;
    // A lossless slot (targeted_sources' PNGs) can only save bytes with fewer texels.
    if (!coding.lossy && !try_downscales) {
      out.bytes += as_is;
      continue;
    }
    SourceImage* decoded = nullptr;
    if (Error e = decode_source(model, image, sources, decoded); e.failed()) return e;
    if (coding.lossy) out.mime = coding.mime;
    const bool srgb = source.slot.color_space == ColorSpace::srgb;
    const TextureSampler& before = source_sampler(source, coding, *decoded);
    const std::vector<SurfaceUvs> uvs = faces_sampling(model, plan, group, built, image);
    // `pixels` through `mime` at quality q, as a viewer will show them.
    // With `at_mips`, also whether it shows what the source shows at every
    // MIP level a minifying viewer samples (Coded::at_mips).
    std::vector<TextureSampler> source_chain;  // built on the first such check
    auto code = [&](const OIIO::ImageBuf& pixels, const std::string& mime, int q, Coded& c,
                    bool at_mips = false) -> Error {
      std::vector<uint8_t> bytes;
      std::string why;
      OIIO::ImageBuf shown;
      if (!encode_image(pixels, mime, q, bytes, why) || !decode_image(bytes, shown, why))
        return {ErrorCode::internal, "image " + std::to_string(image) + ": re-encoding the source: " + why};
      TextureSampler after;
      load_texture_sampler(shown, srgb, coding.gl_wrap_s, coding.gl_wrap_t, source.slot.transform, after);
      c = {};
      c.bytes = bytes.size();
      c.psnr = surface_error(before, after, uvs, kSearchPoints).psnr();
      if (at_mips) {
        if (source_chain.empty()) source_chain = mip_chain(before, kMipLevels + 3);
        c.at_mips = mip_surface_error(source_chain, after, uvs, {kSearchPoints});
      }
      return {};
    };
    // The lowest quality of `pixels` that reaches the target (0: none does),
    // with its file in `best`: PSNR grows with the coder's quality, so
    // bisect on 1..100.
    auto search = [&](const OIIO::ImageBuf& pixels, Coded& best, int& found) -> Error {
      found = 0;
      if (Error e = code(pixels, coding.mime, 100, best); e.failed()) return e;
      if (best.psnr < target_psnr) return {};
      int lo = 1, hi = 100;  // hi reaches the target
      while (lo < hi) {
        const int mid = (lo + hi) / 2;
        Coded c;
        if (Error e = code(pixels, coding.mime, mid, c); e.failed()) return e;
        if (c.psnr >= target_psnr)
          hi = mid, best = c;
        else
          lo = mid + 1;
      }
      found = hi;  // best holds its file: set when hi last moved, or the q100 try
      return {};
    };
    Coded best;
    int quality = 0;
    SourceForm form;
    bool reached = false;
    auto consider = [&](const Coded& c, int q, SourceForm f) {
      if (c.psnr < target_psnr || (reached && c.bytes >= best.bytes)) return;
      best = c, quality = q, form = f, reached = true;
    };
    if (coding.lossy) {
      Coded c;
      int found = 0;
      if (Error e = search(decoded->pixels, c, found); e.failed()) return e;
      if (found > 0) consider(c, found, {});
    }
    // Under rate control the user asked for a quality, not a size: fewer
    // texels may reach it in fewer bytes, as they do for the atlas (its
    // density), through the coder asked or losslessly (sample-sphere at
    // 40 dB: its 512^2 PNG at half size, 49 KB at 42 dB, against JPEG q95's
    // 72 KB at 39.9 dB, whose 4:2:0 chroma loses its colour detail; bench at
    // 689e4e2, baseline 2). Straight alpha would carry transparent texels'
    // colour into their neighbours, so an image with alpha keeps its size.
    const OIIO::ImageSpec& spec = decoded->pixels.spec();
    const bool alpha = spec.alpha_channel >= 0 || spec.nchannels == 2 || spec.nchannels == 4;
    auto wins = [&](const Coded& c) { return c.psnr >= target_psnr && (!reached || c.bytes < best.bytes); };
    // Fewer texels must also show what the source shows where a viewer
    // minifies: at every MIP level, against the source's own chain at the
    // same screen footprint, to the target. A 0.71x image's levels are not
    // the source's levels blended: the truck's at 0.71x reached 40.2 dB at
    // full resolution and 28.8 dB at level 2, and written so at a 40 dB
    // target it rendered at 30.4 dB against the 36.7 dB of its implicit
    // file (bench at 73d4146). So a form that would win is coded again and
    // measured there.
    auto consider_fewer_texels = [&](const OIIO::ImageBuf& pixels, const std::string& mime, const Coded& c,
                                     int q, SourceForm f) -> Error {
      if (!wins(c)) return {};
      Coded again;
      if (Error e = code(pixels, mime, q, again, true); e.failed()) return e;
      for (int l = 0; l < kMipLevels; ++l)
        if (again.at_mips.level[l].values != 0 && again.at_mips.level[l].psnr() < target_psnr) return {};
      consider(c, q, f);
      return {};
    };
    if (try_downscales && !alpha)
      for (double scale : kDownscales) {
        const OIIO::ImageBuf pixels = scaled(decoded->pixels, scale);
        Coded c;
        int found = 0;
        if (coding.lossy) {
          if (Error e = search(pixels, c, found); e.failed()) return e;
          if (found > 0)
            if (Error e = consider_fewer_texels(pixels, coding.mime, c, found, {scale, false}); e.failed())
              return e;
        }
        if (Error e = code(pixels, "image/png", 0, c); e.failed()) return e;
        if (Error e = consider_fewer_texels(pixels, "image/png", c, 0, {scale, true}); e.failed()) return e;
      }
    if (!reached || best.bytes >= as_is) {  // the source as it is is the better file
      out.bytes += as_is;
      continue;
    }
    out.bytes += best.bytes;
    out.psnr = out.psnr > 0 ? std::min(out.psnr, best.psnr) : best.psnr;
    out.quality = std::max(out.quality, quality);
    out.qualities[image] = quality;
    if (form.scale < 1.0) out.forms[image] = form;
  }
  return {};
}

}  // namespace gltfwarp
