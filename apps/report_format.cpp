#include "apps/report_format.h"

#include <cstdio>
#include <filesystem>

namespace gltfwarp::cli {

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
    std::printf("%-10s %-28s %8zu %8zu %9zu %9zu %7u %6.3f %6zu %6.2f %5u\n", id, p.handling.c_str(),
                p.triangles, p.vertices, p.geometry_bytes, p.bitstream_bytes, p.patches, p.max_distortion,
                p.seam_edges, p.rect_fill, p.holes);
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
    if (a.mip_psnr[0] > 0)
      std::printf(
          "  by MIP level 0/1/2/3: mean %.1f/%.1f/%.1f/%.1f dB, worst 1%% of the surface %.1f/%.1f/%.1f/%.1f "
          "dB; "
          "least-squares texels +%.2f dB (%.2f s)\n",
          a.mip_psnr[0], a.mip_psnr[1], a.mip_psnr[2], a.mip_psnr[3], a.worst_psnr[0], a.worst_psnr[1],
          a.worst_psnr[2], a.worst_psnr[3], a.fit_gain_db, a.fit_seconds);
    if (a.atlas_image_bytes > a.source_image_bytes)
      larger += (larger.empty() ? "" : ", ") + std::to_string(i);
  }
  if (!larger.empty())
    std::printf(
        "note: atlas %s: images larger than those replaced (every patch keeps its source detail, plus "
        "gutters; --texel-density 0.8x, --image-format jpeg or a lower --jpeg-quality trade detail for "
        "bytes)\n",
        larger.c_str());
  for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
  std::printf("encoded %s (%llu bytes) -> %s (%llu bytes) in %.2f s\n", in.c_str(),
              static_cast<unsigned long long>(in_size), out.c_str(),
              static_cast<unsigned long long>(out_size), seconds);
}

}  // namespace gltfwarp::cli
