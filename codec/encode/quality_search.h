// Rate control of a lossy image coder (issue 16, item 3): the JPEG or WebP
// quality whose atlas reaches a target surface PSNR with the fewest bytes.
//
// The density is not a second search here: each trial runs the encoder's
// whole density pipeline at one coder quality (the boost toward the target,
// then the adaptive halving that spends the headroom above it), so each
// quality comes back with the density that suits it. Lower qualities cost
// fewer bytes per texel but leave less headroom to halve texels, so the
// fewest bytes usually sit between the ends: a grid from the top down, then
// a bisection around the best.
#pragma once

#include <cstddef>
#include <functional>

#include "codec/core/error.h"

namespace gltfwarp {

struct QualityTrial {
  size_t bytes = 0;  // what the quality costs (the atlas images)
  double psnr = 0;   // and what it shows (the group's worst surface PSNR)
};

struct QualityChoice {
  int quality = 0;       // the chosen coder quality (1..100)
  QualityTrial trial;    // its result
  bool reached = false;  // it reaches the target; false: none did, the closest is chosen
  int trials = 0;        // qualities tried
};

// Tries qualities through `run` (each one once) and returns the reaching
// one with the fewest bytes, else the one that came closest. Quality falls
// with the coder's quality, but only roughly once the density adapts to
// each, so the grid goes down from the top until a clear miss, then halves
// the gap below the best. An error from `run` ends the search with it.
using RunQuality = std::function<Error(int quality, QualityTrial& out)>;
constexpr int kMaxQualityTrials = 9;  // the most qualities one search tries
Error search_image_quality(double target_psnr, const RunQuality& run, QualityChoice& out);

}  // namespace gltfwarp
