// Rate control of a lossy image coder (issue 16, item 3): the JPEG or WebP
// quality whose atlas reaches a target surface PSNR with the fewest bytes.
//
// Each quality comes with the density that suits it: lower qualities cost
// fewer bytes per texel but need more texels, so the fewest bytes usually
// sit between the ends. The density pipeline that finds it (the boost
// toward the target, then the adaptive halving of patch by patch) takes
// seconds per quality, most of it packing and warping layouts that no other
// quality shares. So the search runs in two stages:
//
//   probe  every quality of a grid at a few uniform densities (the same
//          density for every patch, stepped by 2^(1/4)): those layouts are
//          packed and warped once and re-coded per quality (LayoutMemo), so
//          a probe costs a coder pass and a measurement. It tells which
//          qualities can reach the target at all and which reach it in the
//          fewest bytes.
//   run    the whole pipeline, at no more than kMaxAdaptedRuns qualities: from
//          the reaching probe above the probes' cheapest down to the lowest
//          that reaches (three at most), then once between the two cheapest
//          runs.
//
// What is written is the cheapest reaching atlas of all measured, runs and
// probes alike: a probe's uniform layout can be cheaper than what the
// pipeline builds from its floor (TwoSidedPlane at 38 dB).
//
// On CesiumMilkTruck at --target-psnr 40 and 44 the full pipeline at every
// grid quality had chosen q20 and q32; the probes put both inside the
// qualities run.
#pragma once

#include <cstddef>
#include <functional>

#include "codec/core/error.h"

namespace gltfwarp {

struct QualityTrial {
  size_t bytes = 0;  // what the quality costs (the atlas images)
  double psnr = 0;   // and what it shows (the group's worst surface PSNR)
};

// A probe: the cheapest uniform density at the quality that reaches the
// target (`reached`, its bytes and PSNR), else the best PSNR any reached.
struct QualityProbe {
  bool reached = false;
  QualityTrial trial;
};

struct QualityChoice {
  int quality = 0;          // the chosen coder quality (1..100)
  QualityTrial trial;       // its result
  bool reached = false;     // it reaches the target; false: none did, the closest is chosen
  int probes = 0;           // qualities probed
  int trials = 0;           // qualities run through the whole pipeline
  bool from_probe = false;  // the choice is the quality's cheapest reaching probe, not its run
};

using ProbeQuality = std::function<Error(int quality, QualityProbe& out)>;
using RunQuality = std::function<Error(int quality, QualityTrial& out)>;
constexpr int kMaxQualityProbes = 9;            // the grid and two bisections
constexpr int kSpanRuns = 3;                    // the qualities run whole across the probed span
constexpr int kMaxAdaptedRuns = kSpanRuns + 1;  // and one bisection after them

// Probes the grid from the top down until a quality cannot reach the target,
// halves the gap below the lowest that can, then runs the qualities from
// the reaching probe one above the probes' cheapest down to that lowest
// (at most kSpanRuns of them: both ends and the cheapest probe, else one
// between), then the quality halfway between the two cheapest reaching
// runs where they are more than two apart. Returns the reaching run or
// probe with the fewest bytes (`from_probe` says which). When no probe
// reaches, the quality whose probe came closest is run and chosen. Each
// quality is probed and run at most once. An error from either callback
// ends the search with it.
Error search_image_quality(double target_psnr, const ProbeQuality& probe, const RunQuality& run,
                           QualityChoice& out);

}  // namespace gltfwarp
