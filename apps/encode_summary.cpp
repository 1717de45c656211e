#include "apps/encode_summary.h"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace gltfwarp::cli {

namespace {
bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }
}  // namespace

nlohmann::json encode_summary(const EncodeReport& report) {
  int implicit = 0, explicit_uvs = 0, untouched = 0, fallbacks = 0;
  uint64_t patches = 0;
  for (const auto& p : report.primitives) {
    patches += p.patches;
    if (starts_with(p.handling, "implicit-uv")) {
      ++implicit;
    } else if (starts_with(p.handling, "pass") || starts_with(p.handling, "raw: ")) {
      ++untouched;  // "raw: morph targets" stays as it is
    } else {
      ++explicit_uvs;
      if (starts_with(p.handling, "fallback")) ++fallbacks;
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
