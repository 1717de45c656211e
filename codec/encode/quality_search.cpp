#include "codec/encode/quality_search.h"

#include <array>
#include <map>

namespace gltfwarp {

Error search_image_quality(double target_psnr, const RunQuality& run, QualityChoice& out) {
  // Coarse steps: each trial runs the whole density pipeline (seconds on a
  // 2048-px texture set), so few of them, and a bisection where it pays.
  constexpr std::array<int, 7> kGrid = {95, 85, 72, 58, 45, 32, 20};
  constexpr int kBisections = 2;
  static_assert(int(kGrid.size()) + kBisections == kMaxQualityTrials);
  // The adaptive halving stops just above the target wherever it can, so
  // a trial lands within a tenth of a dB of it either side and a near miss
  // says little about the next quality down (its density may land above):
  // only a clear miss ends the descent.
  constexpr double kClearMiss = 1.0;
  std::map<int, QualityTrial> tried;
  auto trial = [&](int q, QualityTrial& t) -> Error {
    if (const auto it = tried.find(q); it != tried.end()) {
      t = it->second;
      return {};
    }
    if (Error e = run(q, t); e.failed()) return e;
    tried[q] = t;
    return {};
  };
  out = {};
  int best = 0;  // the reaching quality with the fewest bytes so far
  QualityTrial t;
  for (int q : kGrid) {
    if (Error e = trial(q, t); e.failed()) return e;
    if (t.psnr < target_psnr) {
      if (t.psnr < target_psnr - kClearMiss) break;
      continue;
    }
    if (best == 0 || t.bytes < tried[best].bytes) best = q;
  }
  if (best == 0) {  // none reaches: the closest
    for (const auto& [q, tq] : tried)
      if (best == 0 || tq.psnr > tried[best].psnr) best = q;
  } else {
    // Between the best and the next grid step down (a miss, or a reaching
    // step with more bytes), halve the gap a few times.
    int low = 0;
    for (size_t i = 0; i + 1 < kGrid.size(); ++i)
      if (kGrid[i] == best) low = kGrid[i + 1];
    int high = best;
    for (int b = 0; b < kBisections && low > 0 && high - low > 2; ++b) {
      const int mid = (high + low) / 2;
      if (Error e = trial(mid, t); e.failed()) return e;
      if (t.psnr >= target_psnr && t.bytes < tried[best].bytes) {
        best = high = mid;
      } else {
        low = mid;
      }
    }
    out.reached = true;
  }
  out.quality = best;
  out.trial = tried[best];
  out.trials = static_cast<int>(tried.size());
  return {};
}

}  // namespace gltfwarp
