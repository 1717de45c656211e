// Rate control (issue 16, item 3): with a target PSNR and a lossy coder the
// encoder picks the coder quality that reaches the target with the fewest
// bytes. The search on synthetic curves with a known answer, then on a real
// model against the fixed quality a user would otherwise type.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "codec/encode/encoder.h"
#include "codec/encode/quality_search.h"
#include "format/gltf/gltf_io.h"
#include "support/corpus.h"

using namespace gltfwarp;
using namespace gltfwarp::test;

namespace {

// PSNR rising with the quality and bytes rising faster near the top, as a
// JPEG at one density behaves.
QualityTrial jpeg_like(int q) { return {size_t(std::lround(1000.0 * std::exp(q / 25.0))), 30.0 + q / 5.0}; }

// The Duck's one atlas, encoded in process with its images as JPEG and a
// 40 dB target (no fallback: the atlas is measured here, not the
// keep-or-fall-back choice). The quality, the target, the format, the
// density adaptation: `set`.
::testing::AssertionResult encode_duck_jpeg(const std::function<void(EncodeOptions&)>& set,
                                            AtlasReport& atlas) {
  const std::string path = corpus_path("Duck");
  if (path.empty()) return ::testing::AssertionFailure() << "Duck is not in the corpus";
  tinygltf::Model model;
  if (!read_gltf(path, model).ok) return ::testing::AssertionFailure() << "cannot read " << path;
  EncodeOptions o;
  o.image_format = "jpeg";
  o.goal_psnr = 40;
  o.quality_fallback = false;
  set(o);
  EncodeReport report;
  if (const Error e = encode_model(model, o, report); e.failed())
    return ::testing::AssertionFailure() << e.message;
  if (report.atlases.size() != 1) return ::testing::AssertionFailure() << report.atlases.size() << " atlases";
  atlas = report.atlases[0];
  return ::testing::AssertionSuccess();
}

}  // namespace

TEST(QualitySearch, FindsTheCheapestReachingQualityOnAMonotoneCurve) {
  // Where the density cannot adapt, a probe and a run are the same atlas.
  std::map<int, int> probes, runs;
  QualityChoice choice;
  const Error e = search_image_quality(
      40.0,
      [&](int q, QualityProbe& p) {
        ++probes[q];
        p = {jpeg_like(q).psnr >= 40.0, jpeg_like(q)};
        return Error();
      },
      [&](int q, QualityTrial& t) {
        ++runs[q];
        t = jpeg_like(q);
        return Error();
      },
      choice);
  ASSERT_FALSE(e.failed());
  ASSERT_TRUE(choice.reached);
  // The true answer is q50 (30 + 50/5 = 40): reached, within the bisection's
  // last gap of it, and no costlier than any grid quality that reaches.
  EXPECT_GE(choice.trial.psnr, 40.0);
  EXPECT_GE(choice.quality, 50);
  EXPECT_LE(choice.quality, 55);
  for (const auto& [q, n] : probes) {
    EXPECT_EQ(n, 1) << "q" << q << " probed twice";
    const QualityTrial t = jpeg_like(q);
    if (t.psnr >= 40.0) {
      EXPECT_LE(choice.trial.bytes, t.bytes) << "q" << q;
    }
  }
  for (const auto& [q, n] : runs) EXPECT_EQ(n, 1) << "q" << q << " run twice";
  EXPECT_EQ(choice.probes, int(probes.size()));
  EXPECT_LE(choice.probes, kMaxQualityProbes);
  EXPECT_EQ(choice.trials, int(runs.size()));
  EXPECT_LE(choice.trials, kMaxAdaptedRuns);
}

// Runs a search on a table of probes: runs not in `adapted` cost
// `otherwise`. The qualities run, in order, go to `runs`.
static QualityChoice search_table(const std::map<int, QualityProbe>& probed,
                                  const std::map<int, QualityTrial>& adapted, QualityTrial otherwise,
                                  std::vector<int>& runs, double target = 40.0) {
  QualityChoice choice;
  const Error e = search_image_quality(
      target,
      [&](int q, QualityProbe& p) {
        const auto it = probed.find(q);
        p = it != probed.end() ? it->second : QualityProbe{false, {0, 39.0}};
        return Error();
      },
      [&](int q, QualityTrial& t) {
        runs.push_back(q);
        const auto it = adapted.find(q);
        t = it != adapted.end() ? it->second : otherwise;
        return Error();
      },
      choice);
  EXPECT_FALSE(e.failed());
  return choice;
}

// The halving spends a quality's headroom on fewer texels, which a uniform
// probe cannot: the cheapest run may sit below the cheapest probe, down to
// the lowest quality that reaches, or one probe step above it. Both ends
// are run and the cheapest probe, then the quality between the two
// cheapest runs.
TEST(QualitySearch, RunsFromAboveTheCheapestProbeDownToTheLowestReachingThenBisects) {
  const std::map<int, QualityProbe> probed = {{95, {true, {30000, 45}}},   {85, {true, {20000, 44}}},
                                              {72, {true, {16000, 42}}},   {58, {true, {12000, 41}}},
                                              {45, {true, {13000, 40.5}}}, {32, {true, {14000, 40.2}}},
                                              {20, {true, {15000, 40.1}}}};
  const std::map<int, QualityTrial> adapted = {
      {72, {10500, 40.1}}, {58, {10000, 40.1}}, {20, {9500, 40.0}}, {39, {9000, 40.0}}};
  std::vector<int> runs;
  const QualityChoice choice = search_table(probed, adapted, {11000, 40.0}, runs);
  EXPECT_EQ(runs, (std::vector<int>{72, 58, 20, 39}));
  EXPECT_TRUE(choice.reached);
  EXPECT_FALSE(choice.from_probe);
  EXPECT_EQ(choice.quality, 39);
  EXPECT_EQ(choice.trial.bytes, 9000u);
  EXPECT_EQ(choice.probes, 7);
  EXPECT_EQ(choice.trials, 4);
  EXPECT_LE(choice.trials, kMaxAdaptedRuns);
}

// The Duck at 38 dB: the lowest grid quality is the cheapest probe, and
// after the halving both it and the step above cost more than the quality
// between them, which the old full search found by bisecting.
TEST(QualitySearch, FindsTheValleyBetweenTheCheapestProbeAndTheStepAbove) {
  const std::map<int, QualityProbe> probed = {{95, {true, {26805, 38.8}}},  {85, {true, {15688, 38.55}}},
                                              {72, {true, {11551, 38.21}}}, {58, {true, {9641, 38.02}}},
                                              {45, {true, {10318, 40.21}}}, {32, {true, {8943, 39.95}}},
                                              {20, {true, {7985, 38.73}}}};
  const std::map<int, QualityTrial> adapted = {{32, {5714, 38.37}}, {20, {6232, 38.36}}, {26, {5241, 39.02}}};
  std::vector<int> runs;
  const QualityChoice choice = search_table(probed, adapted, {99999, 40.0}, runs, 38.0);
  EXPECT_EQ(runs, (std::vector<int>{32, 20, 26}));
  EXPECT_EQ(choice.quality, 26);
  EXPECT_EQ(choice.trial.bytes, 5241u);
}

// TwoSidedPlane at 38 dB: the q72 probe's uniform layout (8,676 B) is
// cheaper than anything the pipeline builds from its floor; what is written
// is the cheapest reaching atlas measured, probe or run.
TEST(QualitySearch, AProbeCheaperThanEveryRunIsChosen) {
  const std::map<int, QualityProbe> probed = {{95, {true, {12635, 40.45}}}, {85, {true, {10177, 40.52}}},
                                              {72, {true, {8676, 40.05}}},  {58, {true, {10720, 40.11}}},
                                              {45, {true, {11352, 40.29}}}, {32, {true, {14087, 40.07}}}};
  std::vector<int> runs;
  const QualityChoice choice = search_table(probed, {}, {13000, 40.4}, runs);
  EXPECT_FALSE(runs.empty());
  EXPECT_TRUE(choice.reached);
  EXPECT_TRUE(choice.from_probe);
  EXPECT_EQ(choice.quality, 72);
  EXPECT_EQ(choice.trial.bytes, 8676u);
  EXPECT_EQ(choice.trials, int(runs.size()));
  // A run as cheap as the probe is preferred (the pipeline's own atlas).
  std::vector<int> again;
  const QualityChoice tie = search_table(probed, {{72, {8676, 40.2}}}, {13000, 40.4}, again);
  EXPECT_FALSE(tie.from_probe);
  EXPECT_EQ(tie.quality, 72);
}

// A quality that cannot reach the target at the densest layout ends the
// descent: the ones below are never probed.
TEST(QualitySearch, AMissEndsTheDescent) {
  std::vector<int> probes;
  QualityChoice choice;
  ASSERT_FALSE(search_image_quality(
                   40.0,
                   [&](int q, QualityProbe& p) {
                     probes.push_back(q);
                     p = {q >= 72, {size_t(q) * 100, q >= 72 ? 41.0 : 39.0}};
                     return Error();
                   },
                   [&](int q, QualityTrial& t) {
                     t = {size_t(q) * 90, 40.5};
                     return Error();
                   },
                   choice)
                   .failed());
  EXPECT_EQ(std::count_if(probes.begin(), probes.end(), [](int q) { return q < 58; }), 0)
      << "probed below the first miss";
  EXPECT_TRUE(choice.reached);
  EXPECT_EQ(choice.quality, 72);  // 65 and 68 (the bisection) miss too
}

// The top quality missing at the densest layout, no lower one can reach:
// that one is run (the closest) and the choice says it missed.
TEST(QualitySearch, NoneReachingGivesTheClosestAndSaysSo) {
  std::vector<int> probes, runs;
  QualityChoice choice;
  ASSERT_FALSE(search_image_quality(
                   45.5,
                   [&](int q, QualityProbe& p) {
                     probes.push_back(q);
                     p = {false, {size_t(q) * 100, 45.0}};
                     return Error();
                   },
                   [&](int q, QualityTrial& t) {
                     runs.push_back(q);
                     t = {size_t(q) * 100, 45.1};
                     return Error();
                   },
                   choice)
                   .failed());
  EXPECT_FALSE(choice.reached);
  EXPECT_EQ(choice.quality, 95);
  EXPECT_EQ(probes, std::vector<int>{95});
  EXPECT_EQ(runs, std::vector<int>{95});
  EXPECT_EQ(choice.trial.psnr, 45.1);
}

TEST(QualitySearch, AnErrorEndsTheSearch) {
  QualityChoice choice;
  int probes = 0, runs = 0;
  const Error e = search_image_quality(
      40.0,
      [&](int, QualityProbe&) {
        ++probes;
        return Error{ErrorCode::internal, "warp failed"};
      },
      [&](int, QualityTrial&) {
        ++runs;
        return Error();
      },
      choice);
  EXPECT_TRUE(e.failed());
  EXPECT_EQ(probes, 1);
  EXPECT_EQ(runs, 0);
  const Error in_run = search_image_quality(
      40.0,
      [&](int q, QualityProbe& p) {
        p = {true, {size_t(q), 41.0}};
        return Error();
      },
      [&](int, QualityTrial&) {
        ++runs;
        return Error{ErrorCode::internal, "pack failed"};
      },
      choice);
  EXPECT_TRUE(in_run.failed());
  EXPECT_EQ(runs, 1);
}

TEST(RateControl, TheDuckReachesTheTargetWithFewerBytesThanAFixedQuality) {
  GLTFWARP_REQUIRE_CORPUS();
  AtlasReport chosen, fixed90;
  std::vector<double> shown;  // the "atlas" progress: rate control's trials move it
  ASSERT_TRUE(encode_duck_jpeg(
      [&](EncodeOptions& o) {
        o.progress = [&](const std::string& stage, double fraction) {
          if (stage == "atlas") shown.push_back(fraction);
        };
      },
      chosen));
  ASSERT_TRUE(encode_duck_jpeg([](EncodeOptions& o) { o.image_quality = 90; }, fixed90));
  std::printf("Duck at 40 dB: rate control q%d%s %zu B %.2f dB (%d probes, %d runs); q90 %zu B %.2f dB\n",
              chosen.image_quality, chosen.lossless_chosen ? " (PNG)" : "", chosen.atlas_image_bytes,
              chosen.psnr, chosen.quality_probes, chosen.quality_trials, fixed90.atlas_image_bytes,
              fixed90.psnr);
  ASSERT_GE(fixed90.psnr, 40.0) << "precondition: the fixed quality reaches the target";
  EXPECT_TRUE(chosen.quality_reached);
  // A JPEG quality, or the lossless atlas where that is smaller still.
  EXPECT_TRUE(chosen.image_quality > 0 || chosen.lossless_chosen);
  EXPECT_GE(chosen.psnr, 40.0);
  EXPECT_LT(chosen.atlas_image_bytes, fixed90.atlas_image_bytes);
  EXPECT_EQ(fixed90.image_quality, 0) << "a quality given is not searched";
  // The whole density pipeline runs at a few qualities only (the rest are
  // probes at uniform densities), and once more losslessly.
  EXPECT_GE(chosen.quality_probes, 1);
  EXPECT_LE(chosen.quality_probes, kMaxQualityProbes);
  EXPECT_LE(chosen.quality_trials, kMaxAdaptedRuns + 1);
  // One step per quality probed or run, one for the lossless candidate, never back.
  EXPECT_TRUE(std::is_sorted(shown.begin(), shown.end()));
  EXPECT_GE(shown.size(),
            size_t(chosen.quality_probes + chosen.quality_trials) + (chosen.lossless_chosen ? 0 : 1));
  ASSERT_FALSE(shown.empty());
  EXPECT_EQ(shown.back(), 1.0);
  EXPECT_GE(shown.front(), 0.0);
}

// A target bounds the adaptive halving ("texels are never halved below
// it"): with a lossy coder the per-patch errors do not add up to the coded
// atlas's, and a round that lands below the target must be undone (the Duck
// at JPEG q50 with --target-psnr 40 fell to 38.1 dB).
TEST(RateControl, HalvingStopsAtTheGoalWithALossyCoder) {
  GLTFWARP_REQUIRE_CORPUS();
  AtlasReport fixed, adaptive;
  for (const bool adapt : {false, true})
    ASSERT_TRUE(encode_duck_jpeg(
        [&](EncodeOptions& o) {
          o.image_quality = 50;
          o.adaptive_density = adapt;
        },
        adapt ? adaptive : fixed));
  std::printf("Duck JPEG q50: fixed density %zu B %.2f dB, adaptive %zu B %.2f dB (source %zu B)\n",
              fixed.atlas_image_bytes, fixed.psnr, adaptive.atlas_image_bytes, adaptive.psnr,
              fixed.source_image_bytes);
  EXPECT_GE(adaptive.psnr, std::min(40.0, fixed.psnr));
  EXPECT_LE(adaptive.atlas_image_bytes, fixed.atlas_image_bytes);
}

// Rate control's lossless candidate: under a JPEG target the atlas the
// encoder writes costs no more image bytes than the same target asked with
// the source's own lossless coding (PNG stays PNG, palette included). At
// 44 dB on the Duck's few-coloured texture PNG is the smaller (the JPEG
// search alone wrote 14.9 KB where PNG needs 9.9 KB), so the encoder must
// write it and say so.
TEST(RateControl, ALosslessAtlasIsWrittenWhereItReachesTheTargetInFewerBytes) {
  GLTFWARP_REQUIRE_CORPUS();
  constexpr double kTarget = 44;
  AtlasReport controlled, lossless;
  ASSERT_TRUE(encode_duck_jpeg([&](EncodeOptions& o) { o.goal_psnr = kTarget; }, controlled));
  ASSERT_TRUE(encode_duck_jpeg(
      [&](EncodeOptions& o) {
        o.goal_psnr = kTarget;
        o.image_format = "keep";
      },
      lossless));
  std::printf("Duck at %.0f dB: JPEG target %zu B %.2f dB (%s; best JPEG q%d %zu B), PNG %zu B %.2f dB\n",
              kTarget, controlled.atlas_image_bytes, controlled.psnr,
              controlled.lossless_chosen ? "PNG chosen" : "JPEG", controlled.lossy_quality_beaten,
              controlled.lossy_bytes_beaten, lossless.atlas_image_bytes, lossless.psnr);
  ASSERT_GE(lossless.psnr, kTarget) << "precondition: the lossless atlas reaches the target";
  EXPECT_GE(controlled.psnr, kTarget);
  EXPECT_LE(controlled.atlas_image_bytes, lossless.atlas_image_bytes);
  ASSERT_TRUE(controlled.lossless_chosen);
  EXPECT_EQ(controlled.atlas_image_bytes, lossless.atlas_image_bytes) << "the same atlas as keep writes";
  EXPECT_LT(controlled.atlas_image_bytes, controlled.lossy_bytes_beaten);
  EXPECT_EQ(controlled.image_quality, 0) << "no JPEG quality is reported for a PNG atlas";
}
