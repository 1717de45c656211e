#include "codec/encode/quality_search.h"

#include <array>
#include <cstdlib>
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

  // The qualities run whole, high to low: from the reaching probe one step
  // above the cheapest down to the lowest reaching (the halving spends a
  // higher quality's headroom on fewer texels, which a uniform probe cannot,
  // so the cheapest probe only marks where the cheapest run lies near), or,
  // none reaching, the closest.
  std::vector<int> candidates;
  int cheapest = 0;  // the cheapest reaching probe
  for (const auto& [q, p] : probed)
    if (p.reached && (cheapest == 0 || p.trial.bytes < probed[cheapest].trial.bytes)) cheapest = q;
  if (lowest == 0) {
    int closest = 0;
    for (const auto& [q, p] : probed)
      if (closest == 0 || p.trial.psnr > probed[closest].trial.psnr) closest = q;
    candidates.push_back(closest);
  } else {
    int above = cheapest;  // the next reaching probe up, if any
    for (const auto& [q, p] : probed)
      if (p.reached && q > cheapest) {
        above = q;
        break;
      }
    for (auto it = probed.rbegin(); it != probed.rend(); ++it)
      if (it->second.reached && it->first <= above && it->first >= lowest) candidates.push_back(it->first);
    if (candidates.size() > size_t(kSpanRuns)) {
      static_assert(kSpanRuns == 3);
      const int between = cheapest != candidates.front() && cheapest != candidates.back()
                              ? cheapest
                              : candidates[candidates.size() / 2];
      candidates = {candidates.front(), between, candidates.back()};
    }
  }
  std::map<int, QualityTrial> ran;
  auto run_at = [&](int q) -> Error {
    QualityTrial t;
    if (Error e = run(q, t); e.failed()) return e;
    ran[q] = t;
    return {};
  };
  for (int q : candidates)
    if (Error e = run_at(q); e.failed()) return e;
  // The reaching run with the fewest bytes other than `except` (0: none).
  auto cheapest_run = [&](int except) {
    int found = 0;
    for (const auto& [q, t] : ran)
      if (q != except && t.psnr >= target_psnr && (found == 0 || t.bytes < ran[found].bytes)) found = q;
    return found;
  };
  // Between the two cheapest reaching runs, where they are more than two
  // apart: the cost over quality after the halving has a valley the grid
  // can step over (the Duck at 38 dB: q32 and q20 both dearer than q26).
  const int first = cheapest_run(0), second = first != 0 ? cheapest_run(first) : 0;
  if (second != 0 && std::abs(first - second) > 2) {
    const int mid = (first + second) / 2;
    if (!ran.count(mid))
      if (Error e = run_at(mid); e.failed()) return e;
  }
  const int best = cheapest_run(0);
  int closest = 0;
  for (const auto& [q, t] : ran)
    if (closest == 0 || t.psnr > ran[closest].psnr) closest = q;
  out.trials = static_cast<int>(ran.size());
  // A probe's uniform layout is an atlas too: the cheapest reaching one is
  // written where no run beat it (TwoSidedPlane at 38 dB: the q72 probe's
  // 8.7 KB atlas, where the pipeline's runs built 13.5 KB at best).
  if (cheapest != 0 && (best == 0 || probed[cheapest].trial.bytes < ran[best].bytes)) {
    out.reached = true;
    out.quality = cheapest;
    out.trial = probed[cheapest].trial;
    out.from_probe = true;
    return {};
  }
  out.reached = best != 0;
  out.quality = best != 0 ? best : closest;
  out.trial = ran[out.quality];
  return {};
}

}  // namespace gltfwarp
