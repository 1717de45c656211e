#include "codec/encode/quality_search.h"

#include <array>
#include <map>
#include <vector>

namespace gltfwarp {

Error search_image_quality(double target_psnr, const ProbeQuality& probe, const RunQuality& run,
                           QualityChoice& out) {
  constexpr std::array<int, 7> kGrid = {95, 85, 72, 58, 45, 32, 20};
  constexpr int kBisections = 2;
  static_assert(int(kGrid.size()) + kBisections == kMaxQualityProbes);
  out = {};
  std::map<int, QualityProbe> probed;
  auto probe_at = [&](int q) -> Error {
    if (probed.count(q)) return {};
    QualityProbe p;
    if (Error e = probe(q, p); e.failed()) return e;
    probed[q] = p;
    return {};
  };
  // Down the grid while the qualities reach the target: a quality that
  // cannot reach it at the densest layout the pipeline may use, the ones
  // below cannot either (the coder's loss only grows).
  int lowest = 0, missing = 0;  // the lowest reaching quality, the highest one known not to
  for (int q : kGrid) {
    if (Error e = probe_at(q); e.failed()) return e;
    if (!probed[q].reached) {
      missing = q;
      break;
    }
    lowest = q;
  }
  for (int b = 0; b < kBisections && lowest > 0 && missing > 0 && lowest - missing > 2; ++b) {
    const int mid = (lowest + missing) / 2;
    if (Error e = probe_at(mid); e.failed()) return e;
    (probed[mid].reached ? lowest : missing) = mid;
  }
  out.probes = static_cast<int>(probed.size());

  // The qualities run whole: from the probes' cheapest down to the lowest
  // reaching (the halving spends a higher quality's headroom on fewer texels,
  // which a uniform probe cannot, so the cheapest probe is only where the
  // cheapest run starts), or, none reaching, the closest.
  std::vector<int> candidates;  // from high to low
  if (lowest == 0) {
    int closest = 0;
    for (const auto& [q, p] : probed)
      if (closest == 0 || p.trial.psnr > probed[closest].trial.psnr) closest = q;
    candidates.push_back(closest);
  } else {
    int cheapest = 0;
    for (const auto& [q, p] : probed)
      if (p.reached && (cheapest == 0 || p.trial.bytes < probed[cheapest].trial.bytes)) cheapest = q;
    for (auto it = probed.rbegin(); it != probed.rend(); ++it)
      if (it->second.reached && it->first <= cheapest && it->first >= lowest) candidates.push_back(it->first);
    if (candidates.size() > size_t(kMaxAdaptedRuns)) {
      static_assert(kMaxAdaptedRuns == 3);
      candidates = {candidates.front(), candidates[candidates.size() / 2], candidates.back()};
    }
  }
  std::map<int, QualityTrial> ran;
  int best = 0, closest = 0;
  for (int q : candidates) {
    QualityTrial t;
    if (Error e = run(q, t); e.failed()) return e;
    ran[q] = t;
    if (t.psnr >= target_psnr && (best == 0 || t.bytes < ran[best].bytes)) best = q;
    if (closest == 0 || t.psnr > ran[closest].psnr) closest = q;
  }
  out.reached = best != 0;
  out.quality = best != 0 ? best : closest;
  out.trial = ran[out.quality];
  out.trials = static_cast<int>(ran.size());
  return {};
}

}  // namespace gltfwarp
