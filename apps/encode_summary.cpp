#include "apps/encode_summary.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace gltfwarp::cli {
namespace {

double round2(double v) { return std::round(v * 100) / 100; }

// How the explicit-UV alternative's images were priced: "lossless"
// (as they are, or smaller PNGs of the same pixels) or the coder and the quality searched ("webp q21").
std::string explicit_images(int quality, const std::string& mime) {
  if (quality <= 0) return "lossless";
  return std::string(mime == "image/webp" ? "webp" : "jpeg") + " q" + std::to_string(quality);
}

// The equal-quality comparison behind each keep-or-fall-back choice (issue
// 16, honest reports): the atlases kept, and the groups that kept explicit
// UVs because that file was smaller.
nlohmann::json equal_quality(const EncodeReport& report) {
  nlohmann::json kept = nlohmann::json::array(), explicit_kept = nlohmann::json::array();
  for (const auto& a : report.atlases)
    if (a.explicit_bytes > 0)
      kept.push_back(
          {{"bytes", a.file_bytes},
           {"psnr_db", round2(a.psnr)},
           {"explicit_bytes", a.explicit_bytes},
           {"explicit_psnr_db",
            a.explicit_psnr > 0 ? nlohmann::json(round2(a.explicit_psnr)) : nlohmann::json()},
           {"explicit_images", explicit_images(a.explicit_image_quality, a.explicit_image_mime)},
           {"image_quality", a.image_quality > 0 ? nlohmann::json(a.image_quality) : nlohmann::json()},
           {"lossless_chosen", a.lossless_chosen}});
  for (const auto& p : report.primitives)
    if (p.handling == Handling::fallback && p.fallback.reason == FallbackReason::explicit_smaller) {
      const Fallback& f = p.fallback;
      explicit_kept.push_back(
          {{"mesh", p.mesh},
           {"primitive", p.primitive},
           {"implicit_bytes", f.implicit_bytes},
           {"atlas_psnr_db", round2(f.psnr)},
           {"explicit_bytes", f.explicit_bytes},
           {"explicit_psnr_db",
            f.explicit_psnr > 0 ? nlohmann::json(round2(f.explicit_psnr)) : nlohmann::json()},
           {"explicit_images", explicit_images(f.explicit_image_quality, f.explicit_image_mime)}});
    }
  return {{"atlases", kept}, {"explicit_kept", explicit_kept}};
}

}  // namespace

nlohmann::json encode_summary(const EncodeReport& report) {
  int implicit = 0, explicit_uvs = 0, untouched = 0, fallbacks = 0;
  uint64_t patches = 0;
  for (const auto& p : report.primitives) {
    patches += p.patches;
    switch (p.handling) {
      case Handling::implicit_uv:
        ++implicit;
        break;
      case Handling::pass_not_triangles:
      case Handling::pass_no_triangles:
      case Handling::pass_unsupported:
      case Handling::raw_morph_targets:  // stays as it is
        ++untouched;
        break;
      case Handling::fallback:
        ++fallbacks;
        ++explicit_uvs;
        break;
      case Handling::draco:
      case Handling::raw:
        ++explicit_uvs;
        break;
    }
  }
  double worst = 0;
  bool measured = false;
  for (const auto& a : report.atlases)
    if (a.psnr > 0) {
      worst = measured ? std::min(worst, a.psnr) : a.psnr;
      measured = true;
    }
  nlohmann::json j;
  j["psnr_db"] = measured ? nlohmann::json(round2(worst)) : nlohmann::json();
  j["handling"] = {{"implicit", implicit}, {"explicit", explicit_uvs}, {"untouched", untouched}};
  j["fallbacks"] = fallbacks;
  j["primitives"] = report.primitives.size();
  j["atlases"] = report.atlases.size();
  j["patches"] = patches;
  j["equal_quality"] = equal_quality(report);
  return j;
}

}  // namespace gltfwarp::cli
