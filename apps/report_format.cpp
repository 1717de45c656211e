#include "apps/report_format.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

namespace gltfwarp::cli {

namespace {

std::string primitive_name(int mesh, int primitive) {
  return "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive);
}

// "JPEG", "WebP": the lossy coder a mimeType names, as the report prints it.
const char* coder_name(const std::string& mime) { return mime == "image/webp" ? "WebP" : "JPEG"; }

// How the equal-quality comparison re-encoded the source images: "as JPEG
// q49", or, where rate control found PNG at fewer texels smallest for every
// one, "as PNG at fewer texels" (quality 0).
std::string re_encoded(const std::string& mime, int quality) {
  if (quality <= 0) return "as PNG at fewer texels";
  return std::string("as ") + coder_name(mime) + " q" + std::to_string(quality);
}

// Appends, when a fallback recoded the source images (--image-format
// jpeg|webp), which coder and quality they were written with.
void append_recoded(char* line, size_t size, const Fallback& f) {
  if (f.images_recoded_quality > 0) {
    const size_t used = std::strlen(line);
    if (f.target_psnr > 0)
      std::snprintf(line + used, size - used, "; the source images written as %s q%d, to reach %.1f dB",
                    coder_name(f.explicit_image_mime), f.images_recoded_quality, f.target_psnr);
    else
      std::snprintf(line + used, size - used, "; the source images written as %s q%d, as asked",
                    coder_name(f.explicit_image_mime), f.images_recoded_quality);
  }
  if (f.images_downscaled > 0) {
    const size_t used = std::strlen(line);
    const char* png = f.images_downscaled_png == 0                     ? ""
                      : f.images_downscaled_png == f.images_downscaled ? ", as PNG"
                                                                       : ", some as PNG";
    std::snprintf(
        line + used, size - used,
        "; %u source image%s written with fewer texels (%.2fx a side%s): the fewest bytes that reach "
        "%.1f dB",
        f.images_downscaled, f.images_downscaled == 1 ? "" : "s", f.images_scale, png, f.target_psnr);
  }
  if (f.images_kept_for_target > 0) {
    const size_t used = std::strlen(line);
    std::snprintf(line + used, size - used,
                  "; %u source image%s kept as %s (%zu bytes): no %s quality reaches %.1f dB in fewer bytes",
                  f.images_kept_for_target, f.images_kept_for_target == 1 ? "" : "s",
                  f.images_kept_for_target == 1 ? "it was" : "they were", f.kept_for_target_bytes,
                  coder_name(f.explicit_image_mime), f.target_psnr);
  }
  if (f.images_kept > 0) {
    const size_t used = std::strlen(line);
    std::snprintf(line + used, size - used,
                  "; %u source image%s kept as %s (%zu bytes): %s q%d would be %zu bytes, and lossy",
                  f.images_kept, f.images_kept == 1 ? "" : "s", f.images_kept == 1 ? "it was" : "they were",
                  f.kept_bytes, coder_name(f.explicit_image_mime), f.kept_recoded_quality,
                  f.kept_recoded_bytes);
  }
  if (f.normal_maps_recoded > 0) {
    const size_t used = std::strlen(line);
    std::snprintf(line + used, size - used, "; %u normal map%s written as %s q%d, as the atlas would have",
                  f.normal_maps_recoded, f.normal_maps_recoded == 1 ? "" : "s",
                  coder_name(f.explicit_image_mime), f.normal_maps_quality);
  }
  if (f.images_repacked > 0) {
    const size_t used = std::strlen(line);
    std::snprintf(line + used, size - used, "; %u source image%s written again losslessly, %zu -> %zu bytes",
                  f.images_repacked, f.images_repacked == 1 ? "" : "s", f.repacked_bytes_before,
                  f.repacked_bytes_after);
  }
}

}  // namespace

std::string fallback_text(const Fallback& f) {
  char line[1024];
  switch (f.reason) {
    case FallbackReason::none:
      return "no reason given";
    case FallbackReason::texcoord_not_vec2:
      return "TEXCOORD_0 is not a VEC2";
    case FallbackReason::no_triangles:
      return "no triangles";
    case FallbackReason::no_triangles_after_draco:
      return "no triangles left after Draco";
    case FallbackReason::embedding_failed:
      return std::string("embedding failed: ") + to_string(f.layout);
    case FallbackReason::below_quality_floor:
      std::snprintf(line, sizeof line,
                    "the warped atlas reached %.1f dB at %.3gx density%s, below --min-psnr %.1f", f.psnr,
                    f.density_factor, f.capped ? " (held by --max-atlas-size)" : "", f.min_psnr);
      append_recoded(line, sizeof line, f);
      return line;
    case FallbackReason::explicit_smaller:
      if (f.explicit_psnr > 0) {
        std::snprintf(line, sizeof line,
                      "smaller at equal quality: %zu bytes of geometry and source images %s (%.1f dB), "
                      "against %zu with the implicit map and a %.1f dB atlas",
                      f.explicit_bytes, re_encoded(f.explicit_image_mime, f.explicit_image_quality).c_str(),
                      f.explicit_psnr, f.implicit_bytes, f.psnr);
        append_recoded(line, sizeof line, f);
      } else {
        std::snprintf(line, sizeof line,
                      "smaller: %zu bytes of geometry and the source images, lossless, against %zu with "
                      "the implicit map and a %.1f dB atlas",
                      f.explicit_bytes, f.implicit_bytes, f.psnr);
        append_recoded(line, sizeof line, f);
      }
      return line;
    case FallbackReason::draco_refused:
      return "Draco cannot carry the geometry";
    case FallbackReason::texcoord_out_of_range:
      std::snprintf(line, sizeof line,
                    "TEXCOORD_0 reaches %.3g, beyond +-%.0f: float UVs that far from 0 cannot place a texel",
                    f.max_source_uv, kMaxSourceUv);
      return line;
    case FallbackReason::texture_repeats:
      std::snprintf(line, sizeof line,
                    "the UVs repeat the texture %.3gx (%.3g texels counted per use, %.3g in the images): the "
                    "atlas would store every repeat",
                    f.image_texels > 0 ? f.texel_uses / f.image_texels : 0.0, f.texel_uses, f.image_texels);
      return line;
  }
  return "?";
}

std::string handling_text(const PrimitiveReport& p) {
  switch (p.handling) {
    case Handling::implicit_uv:
      return p.raw_geometry ? "implicit-uv (raw geometry)" : "implicit-uv";
    case Handling::draco:
      return "draco";
    case Handling::raw:
      return "raw";
    case Handling::raw_morph_targets:
      return "raw: morph targets";
    case Handling::fallback:  // the reason is long: its note line below the table says it
      return "fallback: explicit UVs";
    case Handling::pass_not_triangles:
      return "pass: not triangles (mode " + std::to_string(p.mode) + ")";
    case Handling::pass_no_triangles:
      return "pass: no triangles";
    case Handling::pass_unsupported:  // Draco's message is long: its note line below the table says it
      return "pass: Draco cannot carry it";
  }
  return "?";
}

std::string note_text(const Note& n) {
  const std::string who = primitive_name(n.mesh, n.primitive);
  switch (n.kind) {
    case NoteKind::image_not_decodable:
      return "image " + std::to_string(n.image) + " kept as is, explicit UVs kept for its users: " + n.detail;
    case NoteKind::image_ktx2:
      return "image " + std::to_string(n.image) +
             " kept as is, explicit UVs kept for its users: KTX2 images cannot be decoded and warped";
    case NoteKind::texture_in_extension:
      return who + ": explicit UVs kept, texture " + std::to_string(n.texture) + " has an image in " +
             n.detail + " that the warp cannot rewrite";
    case NoteKind::texture_without_image:
      return who + ": explicit UVs kept, texture " + std::to_string(n.texture) + " has no image";
    case NoteKind::morph_targets_raw:
      return who + " kept raw: Draco cannot carry morph targets";
    case NoteKind::cut_into_parts:
      return who + " cut into " + std::to_string(n.parts) +
             " primitives (the others appended to its mesh): its texels would pass one atlas page "
             "(--max-atlas-size, --max-pages)";
    case NoteKind::fallback:
      return who + ": fallback: explicit UVs kept (" + fallback_text(n.fallback) + ")";
    case NoteKind::no_triangles:
      return who + " passed through: it has no triangles";
    case NoteKind::draco_unsupported:
      return who + " passed through: " + n.detail;
  }
  return "?";
}

void print_encode_report(const EncodeReport& r, const std::string& in, const std::string& out,
                         double seconds) {
  std::error_code ec;
  const auto in_size = std::filesystem::file_size(in, ec);
  const auto out_size = std::filesystem::file_size(out, ec);
  std::printf("%-10s %-28s %8s %8s %9s %9s %7s %6s %6s %6s %5s\n", "primitive", "handling", "tris", "verts",
              "geom B", "uvmap B", "patches", "maxD", "seams", "fill", "holes");
  for (const auto& p : r.primitives) {
    char id[32];
    std::snprintf(id, sizeof id, "%d/%d", p.mesh, p.primitive);
    std::printf("%-10s %-28s %8zu %8zu %9zu %9zu %7u %6.3f %6zu %6.2f %5u\n", id, handling_text(p).c_str(),
                p.triangles, p.vertices, p.geometry_bytes, p.bitstream_bytes, p.patches, p.max_distortion,
                p.seam_edges, p.rect_fill, p.holes);
    // The source's own UV charts beside our patches (implicit UVs only).
    if (p.handling == Handling::implicit_uv && p.source.charts > 0)
      std::printf(
          "%-10s %-28s %8s %8s %9s %9s %7u %6s %6u %6s %5s   (%u of them bound our patches; "
          "%.1f%% of the surface past tau at each chart's own scale; not discs: %u charts, %.1f%% of the "
          "surface)\n",
          "", "  source UV charts", "", "", "", "", p.source.charts, "", p.source.seam_edges, "", "",
          p.source.bound_seam_edges, 100.0 * p.source.area_beyond_tau, p.source.non_disc_charts,
          100.0 * p.source.non_disc_area);
    if (p.greedy.patches > 0)
      std::printf("%-10s %-28s %8s %8s %9s %9s %7u %6s %6u %6.2f %5u   (ours: %.0f%% of greedy's seams)\n",
                  "", "  greedy baseline", "", "", "", "", p.greedy.patches, "", p.greedy.seam_edges,
                  p.greedy.rect_fill, p.greedy.holes,
                  p.greedy.seam_edges ? 100.0 * double(p.seam_edges) / p.greedy.seam_edges : 0.0);
  }
  std::string larger;  // atlases whose images outweigh the source's
  for (size_t i = 0; i < r.atlases.size(); ++i) {
    const auto& a = r.atlases[i];
    std::string pages;
    for (size_t p = 1; p < a.page_sizes.size(); ++p)
      pages += (p == 1 ? " + " : ", ") + std::to_string(a.page_sizes[p][0]) + "x" +
               std::to_string(a.page_sizes[p][1]);
    std::printf(
        "atlas %zu: %ux%u%s, fill %.1f%%, overlapping texels %zu, density %.3gx, surface PSNR %.1f dB, "
        "images %zu -> %zu bytes\n",
        i, a.width, a.height, pages.c_str(), 100.0 * a.fill, a.overlapping_texels, a.density_factor, a.psnr,
        a.source_image_bytes, a.atlas_image_bytes);
    if (a.image_quality > 0)
      std::printf("  rate control: %s q%d %s%s (%d qualities probed, %d run whole)\n",
                  a.quality_reached ? "chose" : "kept", a.image_quality,
                  a.quality_reached ? "as the fewest bytes reaching the target"
                                    : "as the closest tried: none reached the target",
                  a.quality_uniform ? ", at a uniform density" : "", a.quality_probes, a.quality_trials);
    if (a.lossless_chosen)
      std::printf(
          "  rate control: chose PNG, as it reaches the target in fewer bytes than the best lossy quality "
          "tried "
          "(q%d: %zu bytes; %d qualities probed, %d settings run whole)\n",
          a.lossy_quality_beaten, a.lossy_bytes_beaten, a.quality_probes, a.quality_trials);
    if (a.reused_patches > 0)
      std::printf("  texel reuse: %u patches land on the texels of congruent ones (%.0f texels saved)\n",
                  a.reused_patches, a.reused_texels);
    if (a.aligned_patches > 0)
      std::printf("  texel-exact: %u patches hold their source's own texels (not resampled)\n",
                  a.aligned_patches);
    if (a.mip_psnr[0] > 0)
      std::printf(
          "  by MIP level 0/1/2/3: mean %.1f/%.1f/%.1f/%.1f dB, worst 1%% of the surface %.1f/%.1f/%.1f/%.1f "
          "dB; "
          "least-squares texels +%.2f dB (%.2f s)\n",
          a.mip_psnr[0], a.mip_psnr[1], a.mip_psnr[2], a.mip_psnr[3], a.worst_psnr[0], a.worst_psnr[1],
          a.worst_psnr[2], a.worst_psnr[3], a.fit_gain_db, a.fit_seconds);
    if (a.explicit_bytes > 0) {
      if (a.explicit_psnr > 0)
        std::printf(
            "  with explicit UVs at equal quality: %zu bytes (source images %s, %.1f dB); "
            "implicit: %zu bytes (%.1f dB), %+.1f%%\n",
            a.explicit_bytes, re_encoded(a.explicit_image_mime, a.explicit_image_quality).c_str(),
            a.explicit_psnr, a.file_bytes, a.psnr,
            100.0 * (double(a.file_bytes) / double(a.explicit_bytes) - 1));
      else
        std::printf(
            "  with explicit UVs: %zu bytes (source images lossless); implicit: %zu bytes "
            "(%.1f dB), %+.1f%%\n",
            a.explicit_bytes, a.file_bytes, a.psnr,
            100.0 * (double(a.file_bytes) / double(a.explicit_bytes) - 1));
    }
    if (a.atlas_image_bytes > a.source_image_bytes)
      larger += (larger.empty() ? "" : ", ") + std::to_string(i);
  }
  if (!larger.empty())
    std::printf(
        "note: atlas %s: images larger than those replaced (every patch keeps its source detail, plus "
        "gutters; --texel-density 0.8x, --image-format jpeg or webp, or a lower --image-quality trade detail "
        "for "
        "bytes)\n",
        larger.c_str());
  for (const auto& n : r.notes) std::printf("note: %s\n", note_text(n).c_str());
  std::printf("encoded %s (%llu bytes) -> %s (%llu bytes) in %.2f s\n", in.c_str(),
              static_cast<unsigned long long>(in_size), out.c_str(),
              static_cast<unsigned long long>(out_size), seconds);
}

}  // namespace gltfwarp::cli
