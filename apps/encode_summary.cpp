#include "apps/encode_summary.h"

#include <algorithm>
#include <cmath>

namespace gltfwarp::cli {

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
  j["psnr_db"] = measured ? nlohmann::json(std::round(worst * 100) / 100) : nlohmann::json();
  j["handling"] = {{"implicit", implicit}, {"explicit", explicit_uvs}, {"untouched", untouched}};
  j["fallbacks"] = fallbacks;
  j["primitives"] = report.primitives.size();
  j["atlases"] = report.atlases.size();
  j["patches"] = patches;
  return j;
}

}  // namespace gltfwarp::cli
