// A process that encodes many files (an asset pipeline linking the
// encoder, the benchmark's rate-distortion ladder) must hold the memory of
// one encode, not of all. OIIO 2.4's texture system, asked to make its own
// private image cache, did not free it on destroy: each warp kept its
// tiles, about 23 MB per Duck encode, and the benchmark's truck ladder grew
// past 15 GB. The warp now owns the cache and tears it down (warp.cpp).
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "codec/encode/encoder.h"
#include "tests/support/testing/sample_model.h"

namespace gltfwarp {
namespace {

// Resident set of this process, in KiB (Linux /proc).
long resident_kib() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;  // ASan's quarantine holds freed memory: RSS says nothing there
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

TEST(RepeatedEncodes, HoldTheMemoryOfOne) {
  if (kSanitized) GTEST_SKIP() << "RSS is not a measure under AddressSanitizer";
  tinygltf::Model source;
  ASSERT_EQ(make_sample_model("plane", 200, 1024, source), "");
  std::vector<long> rss;
  for (int run = 0; run < 6; ++run) {
    tinygltf::Model model = source;
    EncodeOptions options;
    options.quality_fallback = false;  // always the implicit map: every run warps
    options.adaptive_density = false;  // one warp per encode, and a fast coder
    options.image_format = "jpeg";
    options.image_quality = 80;
    EncodeReport report;
    ASSERT_FALSE(encode_model(model, options, report).failed());
    rss.push_back(resident_kib());
  }
  ASSERT_GT(rss[0], 0);
  // After the first two (allocator arenas, OIIO's one-time set-up), the
  // resident set stays level: four more encodes may not add 16 MiB.
  EXPECT_LT(rss[5] - rss[1], 16 * 1024) << "RSS after each encode (KiB): " << rss[0] << " " << rss[1] << " "
                                        << rss[2] << " " << rss[3] << " " << rss[4] << " " << rss[5];
}

}  // namespace
}  // namespace gltfwarp
