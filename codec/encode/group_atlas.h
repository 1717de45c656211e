// One atlas group's atlas at one texel density, built without touching the
// model (so the encoder can measure it, try again or give up), in stages a
// reader can follow in order:
//
//   choose_density   texels per layout unit: the source's detail, per face (group_layout.cpp)
//   pack_group       members over pages, patches packed on each page (group_layout.cpp)
//   write_streams    the bitstreams, and the UVs exactly as decode_uvs rebuilds them (group_layout.cpp)
//   per slot source and page (group_images.cpp):
//     warp_page_image    the source texture warped into the page
//     code_page_image    palette snapping and the file's bytes (PNG or JPEG)
//     measure_page_image surface error of what a viewer will show, per patch
//
// build_group_atlas runs every stage for an atlas the file may hold;
// measure_group_atlas runs what an adaptive round's trial needs (each
// patch's texels and error) and skips the rest (group_atlas.cpp).
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <tiny_gltf.h>

#include "codec/core/error.h"
#include "codec/encode/encoder.h"
#include "codec/encode/implicit_uv_encoder.h"
#include "codec/encode/texture/mip_quality.h"
#include "codec/encode/texture/png_palette.h"
#include "codec/encode/texture/texture_sampler.h"
#include "codec/encode/texture/warp.h"
#include "codec/encode/texture/warp_quality.h"
#include "format/bitstream/uvmap.h"

namespace gltfwarp {

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

struct GroupAtlas {
  AtlasReport report;
  std::vector<UvMap> maps;                       // per member
  std::vector<std::vector<uint8_t>> bitstreams;  // per member
  std::vector<WarpJob> jobs;
  SurfaceError error;  // colour slots: warped atlas against the source
  MipQuality mip;      // the same at MIP levels 0..3 with worst regions (measure_mip_levels)
  double fit_before = 0, fit_after = 0;  // least-squares fit errors, colour slots
  // The same per source image (pages pooled). The quality floor holds for
  // each image, so each material variant (usually its own images) keeps it,
  // not only the group's images on average.
  std::map<int, SurfaceError> image_error;
  double floor_psnr() const {
    double worst = error.values != 0 ? error.psnr() : 0;
    for (const auto& [image, e] : image_error)
      if (e.values != 0) worst = std::min(worst, e.psnr());
    return worst;
  }
  bool capped = false;       // the atlas was shrunk to fit --max-atlas-size
  bool coded = true;         // every job holds its bytes (build_group_atlas's code_floor)
  uint32_t patch_count = 0;  // over the members, numbered member by member
  std::vector<std::vector<uint32_t>> group_patch;  // per member, per face: its patch in that numbering
  std::vector<SurfaceError> patch_error;           // per patch, colour slots
  std::vector<double> patch_texels;                // per patch: its triangles' area in atlas texels
  std::vector<std::vector<size_t>> pages;          // members (indices into group.members) per page
  std::vector<uint32_t> page_of_member;
};

// Decoded source images by image index: a group's atlas is built up to five
// times (density retries, adaptive rounds), its sources decoded once.
// With each, what every build derives from it alone: its palette and its
// sampler for the quality check (the truck: 12 builds, 0.15 s each).
struct SourceImage {
  OIIO::ImageBuf pixels;
  std::optional<std::vector<PaletteEntry>> palette;  // source_palette, once asked for
  std::map<JobKey, TextureSampler> samplers;
  std::map<JobKey, SourceSamples> source_samples;  // each sampler's values at the measured points
  // Staged for the warp (warp.h), per slot encoding: every page and every
  // density round of the group warps from the one staging.
  std::map<SlotEncoding, std::shared_ptr<const StagedSource>> staged;
};
using SourceImages = std::map<int, SourceImage>;

// Per member, per patch: the scale steps added to the packer's choice
// (adaptive density; empty: none).
using StepBias = std::vector<std::vector<int32_t>>;

// Layouts kept for the builds after, while rate control tries coder
// qualities (choose_image_quality). Each quality's density pipeline starts
// from the same layouts: every patch at its measured scale at each density
// factor, then every patch halved once. Only its later rounds, steered by
// that quality's own error, differ (CesiumMilkTruck at --target-psnr 44:
// 23 of 126 layouts were repeats). Neither the layout nor the warp depends
// on the coder's quality, so a repeat is copied from here, bit for bit,
// instead of being packed and warped again. Only layouts whose step bias
// is one value for every patch are kept, and their warped pages up to a
// bound on memory.
struct LayoutMemo {
  // A warped page before palette snapping and coding, with its warp's report.
  struct Page {
    OIIO::ImageBuf atlas;
    WarpReport report;
  };
  struct Entry {
    LayoutMemo* memo = nullptr;
    bool filled = false;                                // the layout is built
    GroupAtlas layout;                                  // as the layout stages left it: no image yet
    std::map<std::pair<JobKey, uint32_t>, Page> pages;  // by slot source and page
    // The page warped before, if kept: into `atlas` (and `report`).
    bool take(const JobKey& key, uint32_t page, OIIO::ImageBuf& atlas, WarpReport* report) const;
    // Keeps a copy of a warped page, while the memo's bound allows.
    void keep(const JobKey& key, uint32_t page, const OIIO::ImageBuf& atlas, const WarpReport& report);
  };
  // The entry of a layout (`found`: built before, `layout` holds it), or
  // null where such layouts are not kept.
  Entry* find_or_add(double density_factor, const StepBias& step_bias, int effort,
                     const std::string& image_format, bool& found);
  static constexpr size_t kMaxWarpedBytes = size_t(512) << 20;
  size_t warped_bytes = 0;
  std::map<std::tuple<uint64_t, bool, int32_t, int, std::string>, std::unique_ptr<Entry>> entries;
};

// Every stage, for an atlas the file may hold: the tightest packing, every
// slot (normal maps too) coded in its output format. With `code_floor` > 0
// an atlas whose quality (floor_psnr) ends below it, which the caller will
// not keep, may be left without its losslessly coded bytes (out.coded false).
// With a memo, a layout built before is taken from it.
Error build_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                        const EncodeOptions& options, SourceImages& sources, double density_factor,
                        const StepBias& step_bias, GroupAtlas& out, double code_floor = 0,
                        LayoutMemo* memo = nullptr);

// An adaptive round's trial: each patch's texels (patch_texels) and error
// (patch_error), and whether the atlas was capped. One packing order, colour
// slots only, and bytes only where coding loses detail (JPEG: its loss is
// part of the error).
Error measure_group_atlas(const tinygltf::Model& model, ImplicitPlan& plan, const AtlasGroup& group,
                          const EncodeOptions& options, SourceImages& sources, double density_factor,
                          const StepBias& step_bias, GroupAtlas& out, LayoutMemo* memo = nullptr);

// ---- The stages (group_layout.cpp) ----

// Numbers the patches across the group's members: out.patch_count,
// group_patch, and a zero patch_error per patch.
void number_patches(const ImplicitPlan& plan, const AtlasGroup& group, GroupAtlas& out);

// Texel density: keep the source's detail (largest image each member samples).
// Texel reuse: patch p of ip is a copy, placed (fine) on its original's
// texels; it paints and takes none of its own. A fine placement alone is
// no copy: texel-exact patches are fine too (texel_alignment.h).
inline bool is_texel_copy(const ImplicitPrimitive& ip, const UvMap& map, uint32_t p) {
  return !ip.reuse_of.empty() && ip.reuse_of[p] >= 0 && map.placements[p].fine;
}

struct GroupDensity {
  double factor = 1;     // asked: times the measured density
  double scale = 0;      // texels per layout unit the packer is asked for
  double reference = 0;  // the measured (auto) scale; 0 with a fixed --texel-density
  // Per member, per face: texels per layout unit the source gives it (the
  // tau stretch counts), so the packer can give each patch its own scale step.
  std::vector<std::vector<double>> face_density;
  // Per member: the one size of every image its TEXCOORD_0 slots sample,
  // without texture transforms (aligned_uv0_image); 0 x 0: no texel-exact patches.
  std::vector<std::pair<uint32_t, uint32_t>> align_size;
};
GroupDensity choose_density(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                            const EncodeOptions& options, double density_factor);

// How hard the packer looks for the tightest page.
enum class PackEffort {
  tightest,   // several packing orders (an atlas the file may hold)
  one_order,  // a measurement needs each patch's texels, not the tightest page
};

// Pages by estimate, then each page packed: out.pages, maps, page_of_member,
// capped, and the report's page sizes, fill, overlap and density factor.
Error pack_group(const ImplicitPlan& plan, const AtlasGroup& group, const EncodeOptions& options,
                 const GroupDensity& density, const StepBias& step_bias, PackEffort effort, GroupAtlas& out);

// The bitstreams (out.bitstreams), the UVs exactly as the decoder will
// rebuild them (each member's corner_uv in the plan) and out.patch_texels.
Error write_streams(ImplicitPlan& plan, const AtlasGroup& group, const EncodeOptions& options,
                    GroupAtlas& out);

// Each member's corner_uv decoded again from `built`'s bitstreams: the plan
// as build_group_atlas(built) left it, after trial atlases (measurements,
// rejected rounds) wrote theirs. A build is a pure function of the plan and
// its arguments apart from corner_uv, so this stands in for rebuilding.
Error follow_streams(ImplicitPlan& plan, const AtlasGroup& group, const GroupAtlas& built);

// ---- The image stages (group_images.cpp) ----

// One TEXCOORD_0 slot source of the group's materials, warped once per page.
struct SlotSource {
  JobKey key;
  int image = -1;
  TextureSlot slot;
};

// The group's distinct slot sources, in material and slot order.
std::vector<SlotSource> slot_sources(const tinygltf::Model& model, const AtlasGroup& group);

// The decoded source image (decoded once, kept in `sources`).
Error decode_source(const tinygltf::Model& model, int image, SourceImages& sources, SourceImage*& decoded);

// How one slot source is warped and written.
// The format a warped image is written in: the source's unless asked
// otherwise (judged by its bytes: a URI image often has no mimeType);
// formats we do not write (WebP, ...) become PNG.
std::string output_mime(std::span<const uint8_t> source, const std::string& wanted);

struct SlotCoding {
  WarpOptions warp;
  int gl_wrap_s = 0, gl_wrap_t = 0;
  std::string mime;    // of the atlas image
  int quality = 90;    // JPEG/WebP
  bool lossy = false;  // JPEG/WebP colour: what a viewer shows is the decoded bytes
};
SlotCoding slot_coding(const tinygltf::Model& model, const SlotSource& source, const EncodeOptions& options);

// Warps the slot source into page `page` of the built atlas (the members on
// that page that sample its image). `uvs`: those members' source and atlas
// UVs with their patches, for the measurement; `report`, if given, the
// warp's (its least-squares fit). False: no member on the page samples the
// image (nothing warped). The source is staged once, in `decoded`.
// `kept`: the layout's memo entry, if it has one (the warp is taken from it, or kept there).
bool warp_page_image(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                     const GroupAtlas& built, const SlotSource& source, const SlotCoding& coding,
                     SourceImage& decoded, uint32_t page, OIIO::ImageBuf& atlas, std::vector<SurfaceUvs>& uvs,
                     Error& error, WarpReport* report = nullptr, LayoutMemo::Entry* kept = nullptr);

// Snaps the warped page to the palette it will be written with (PNG kept
// as PNG keeps its source's palette), so the quality check measures the
// texels the file will hold. Returns that palette (empty: truecolour).
std::span<const PaletteEntry> snap_page_image(const tinygltf::Model& model, const SlotSource& source,
                                              const SlotCoding& coding, const EncodeOptions& options,
                                              SourceImage& decoded, OIIO::ImageBuf& atlas);

// The file's bytes of a snapped page image.
Error code_page_image(const OIIO::ImageBuf& atlas, std::span<const PaletteEntry> palette,
                      const SlotCoding& coding, std::vector<uint8_t>& bytes);

// Whether the member samples `image` through TEXCOORD_0 in any material it can show.
bool samples_image(const tinygltf::Model& model, const ImplicitPrimitive& ip, int image);

// The source as a viewer samples it through the slot (cached in `decoded`, per slot key).
const TextureSampler& source_sampler(const SlotSource& source, const SlotCoding& coding,
                                     SourceImage& decoded);

// A coded page as a viewer samples it (`shown`: the page image, or its
// coded bytes decoded back), for comparison with the slot's source.
TextureSampler page_sampler(const SlotSource& source, const OIIO::ImageBuf& shown);

// Surface error of `shown` against the source: into the atlas's error, the
// image's and each patch's. Colour slots only: normal maps change
// legitimately (new tangent frames). MIP levels: measure_mip_levels.
void measure_page_image(const SlotSource& source, const SlotCoding& coding, SourceImage& decoded,
                        const OIIO::ImageBuf& shown, std::span<const SurfaceUvs> uvs, GroupAtlas& out);

// The members' source and atlas UVs on `page` that show `image`, with their
// patches: what the page's measurements compare.
std::vector<SurfaceUvs> page_surface_uvs(const tinygltf::Model& model, const ImplicitPlan& plan,
                                         const AtlasGroup& group, const GroupAtlas& built, int image,
                                         uint32_t page);

// The MIP figures of the atlas the file keeps (report only), into
// built.mip and its report: MIP levels 0..3 and worst regions of every
// colour page, from its coded bytes. Four passes per page, so they are
// measured once, on the final build, not in every density round's.
Error measure_mip_levels(const tinygltf::Model& model, const ImplicitPlan& plan, const AtlasGroup& group,
                         const EncodeOptions& options, SourceImages& sources, GroupAtlas& built);

// The MIP reference (mip_quality.h) of a slot source, from every face of
// the group that shows its image: for measure_mip_levels on each page.
std::vector<TextureSampler> group_mip_reference(const tinygltf::Model& model, const ImplicitPlan& plan,
                                                const AtlasGroup& group, const SlotSource& source,
                                                const SlotCoding& coding, SourceImage& decoded);

}  // namespace gltfwarp
