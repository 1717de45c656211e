// The fills of an atlas's empty texels (codec/encode/texture/atlas_fill.h).
// Pull-push: kept texels stay as they are, every filled texel is a blend of
// kept ones (so within their range), and a fill follows the side it is
// nearer to. Nearest: every filled texel is a copy of a nearest kept one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "codec/encode/texture/atlas_fill.h"

namespace gltfwarp {
namespace {

template <typename T>
void check_random(bool deep) {
  std::mt19937 rng(deep ? 7 : 3);
  for (const auto [w, h, nch] :
       {std::array<int, 3>{1, 1, 3}, {7, 5, 1}, {33, 17, 3}, {64, 64, 4}, {1, 40, 2}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(nch));
    const size_t n = size_t(w) * h;
    std::vector<T> px(n * nch);
    std::vector<uint8_t> empty(n);
    const int top = deep ? 65535 : 255;
    for (size_t i = 0; i < n; ++i) {
      empty[i] = rng() % 4 != 0;  // a quarter kept
      for (int c = 0; c < nch; ++c) px[i * nch + c] = T(rng() % (top + 1));
    }
    empty[n / 2] = 0;  // at least one kept
    const std::vector<T> before = px;
    pull_push_fill(reinterpret_cast<uint8_t*>(px.data()), w, h, nch, deep, empty);
    for (int c = 0; c < nch; ++c) {
      T lo = T(top), hi = 0;
      for (size_t i = 0; i < n; ++i)
        if (!empty[i]) lo = std::min(lo, before[i * nch + c]), hi = std::max(hi, before[i * nch + c]);
      for (size_t i = 0; i < n; ++i) {
        if (!empty[i]) {
          ASSERT_EQ(px[i * nch + c], before[i * nch + c]) << "kept texel " << i << " changed";
        } else {
          ASSERT_GE(px[i * nch + c], lo) << i;
          ASSERT_LE(px[i * nch + c], hi) << i;
        }
      }
    }
  }
}

TEST(AtlasFill, KeepsKeptTexelsAndBlendsWithinTheirRange) {
  check_random<uint8_t>(false);
  check_random<uint16_t>(true);
}

TEST(AtlasFill, FollowsTheNearerSide) {
  // Kept: a red column on the left, a blue one on the right; between them empty.
  const int w = 40, h = 9;
  std::vector<uint8_t> px(size_t(w) * h * 3, 0), empty(size_t(w) * h, 1);
  for (int y = 0; y < h; ++y)
    for (int x : {0, 1, 38, 39}) {
      const size_t i = size_t(y) * w + x;
      empty[i] = 0;
      px[3 * i] = x < 20 ? 255 : 0;
      px[3 * i + 2] = x < 20 ? 0 : 255;
    }
  pull_push_fill(px.data(), w, h, 3, false, empty);
  for (int y = 0; y < h; ++y) {
    auto red = [&](int x) { return px[3 * (size_t(y) * w + x)]; };
    auto blue = [&](int x) { return px[3 * (size_t(y) * w + x) + 2]; };
    for (int x = 2; x < 12; ++x) {
      EXPECT_GT(red(x), blue(x)) << x;
    }
    for (int x = 28; x < 38; ++x) {
      EXPECT_LT(red(x), blue(x)) << x;
    }
    for (int x = 2; x < 38; ++x) {  // from red to blue along the row
      EXPECT_GE(red(x), red(x + 1)) << x;
    }
  }
}

TEST(AtlasFill, NothingKeptGivesZeroAndBadSizesAreIgnored) {
  std::vector<uint8_t> px(4 * 4 * 3, 200), empty(16, 1);
  pull_push_fill(px.data(), 4, 4, 3, false, empty);
  EXPECT_TRUE(std::all_of(px.begin(), px.end(), [](uint8_t v) { return v == 0; }));
  std::vector<uint8_t> keep(px.size(), 9);
  const std::vector<uint8_t> before = keep;
  pull_push_fill(keep.data(), 4, 4, 3, false, std::vector<uint8_t>(15, 1));  // mask too short
  pull_push_fill(keep.data(), 0, 4, 3, false, {});
  pull_push_fill(keep.data(), 4, 4, 9, false, empty);  // too many channels
  EXPECT_EQ(keep, before);
}

// flatten_empty_blocks: a block with no kept texel becomes its own mean, a
// block with one kept texel is left as it was, and partial blocks at the
// right and bottom edges count as blocks.
TEST(AtlasFill, FlattensOnlyWhollyEmptyBlocksToTheirMean) {
  const int w = 20, h = 13, nch = 3;  // blocks of 8: 3 x 2, the last column and row partial
  std::mt19937 rng(11);
  std::vector<uint8_t> px(size_t(w) * h * nch), empty(size_t(w) * h, 1);
  for (uint8_t& v : px) v = uint8_t(rng() % 256);
  empty[size_t(2) * w + 3] = 0;    // block (0, 0) keeps one texel
  empty[size_t(12) * w + 17] = 0;  // so does the partial block (2, 1)
  const std::vector<uint8_t> before = px;
  flatten_empty_blocks(px.data(), w, h, nch, false, empty, 8);
  for (int by = 0; by < 2; ++by)
    for (int bx = 0; bx < 3; ++bx) {
      const bool kept = (bx == 0 && by == 0) || (bx == 2 && by == 1);
      const int x0 = 8 * bx, y0 = 8 * by, x1 = std::min(w, x0 + 8), y1 = std::min(h, y0 + 8);
      for (int c = 0; c < nch; ++c) {
        double sum = 0;
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) sum += before[(size_t(y) * w + x) * nch + c];
        const auto mean = uint8_t(std::lround(sum / ((x1 - x0) * (y1 - y0))));
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) {
            const size_t i = (size_t(y) * w + x) * nch + c;
            ASSERT_EQ(px[i], kept ? before[i] : mean)
                << "block " << bx << "," << by << " texel " << x << "," << y;
          }
      }
    }
  // Bad sizes change nothing.
  const std::vector<uint8_t> now = px;
  flatten_empty_blocks(px.data(), w, h, nch, false, std::vector<uint8_t>(7, 1), 8);
  flatten_empty_blocks(px.data(), w, h, nch, false, empty, 0);
  EXPECT_EQ(px, now);
}

// nearest_fill against brute force: every kept texel carries its own index
// (two 16-bit channels), so each filled texel names the texel it copied,
// which must be kept and at the least squared distance of any kept texel.
// Masks from dense to a single kept texel, and one- and two-texel-wide
// pages, where the column pass alone or the row pass alone decides.
TEST(AtlasFill, NearestFillCopiesANearestKeptTexel) {
  std::mt19937 rng(11);
  for (const std::array<int, 3>& page : {std::array<int, 3>{1, 1, 1},
                                         {1, 40, 7},
                                         {40, 1, 7},
                                         {2, 33, 5},
                                         {33, 17, 3},
                                         {64, 48, 50},
                                         {97, 61, 400},
                                         {50, 50, 100000}}) {
    // Named values, not a structured binding: the lambda below captures
    // them (clang before 16 cannot capture a binding).
    const int w = page[0], h = page[1], keep_one_in = page[2];
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + ", one in " + std::to_string(keep_one_in));
    const size_t n = size_t(w) * h;
    std::vector<uint16_t> px(n * 2);
    std::vector<uint8_t> empty(n);
    for (size_t i = 0; i < n; ++i) {
      empty[i] = rng() % uint32_t(keep_one_in) != 0;
      px[2 * i] = uint16_t(i & 0xFFFF), px[2 * i + 1] = uint16_t(i >> 16);
    }
    empty[rng() % n] = 0;  // at least one kept
    const std::vector<uint16_t> before = px;
    nearest_fill(reinterpret_cast<uint8_t*>(px.data()), w, h, 2, true, empty);
    for (size_t i = 0; i < n; ++i) {
      const size_t from = size_t(px[2 * i]) | size_t(px[2 * i + 1]) << 16;
      ASSERT_LT(from, n) << i;
      if (!empty[i]) {
        ASSERT_EQ(from, i) << "kept texel " << i << " changed";
        continue;
      }
      ASSERT_FALSE(empty[from]) << i << " copied the empty texel " << from;
      const auto d2 = [&](size_t a, size_t b) {
        const long dx = long(a % size_t(w)) - long(b % size_t(w)),
                   dy = long(a / size_t(w)) - long(b / size_t(w));
        return dx * dx + dy * dy;
      };
      long best = -1;
      for (size_t k = 0; k < n; ++k)
        if (!empty[k] && (best < 0 || d2(i, k) < best)) best = d2(i, k);
      ASSERT_EQ(d2(i, from), best) << "texel " << i << " copied " << from;
    }
  }
}

// With a reach: texels within it are nearest copies as above; farther
// ones continue their row (a left neighbour's copy, a leading run the
// row's first near texel), and rows with no near texel copy the row above
// (at the top, the first row that has one). Kept texels in a band of
// rows, so that rows above, below and between are wholly far.
TEST(AtlasFill, NearestFillRunsAlongRowsBeyondItsReach) {
  const int w = 61, h = 47;
  const double reach = 3.5;
  std::mt19937 rng(5);
  const size_t n = size_t(w) * h;
  std::vector<uint16_t> px(n * 2);
  std::vector<uint8_t> empty(n, 1);
  for (size_t i = 0; i < n; ++i) px[2 * i] = uint16_t(i & 0xFFFF), px[2 * i + 1] = uint16_t(i >> 16);
  for (int y = 15; y < 22; ++y)  // rows 15-21 hold kept texels; 0-10 and 26-46 are beyond reach
    for (int x = 20; x < w; ++x) empty[size_t(y) * w + x] = rng() % 9 != 0;
  const std::vector<uint16_t> before = px;
  nearest_fill(reinterpret_cast<uint8_t*>(px.data()), w, h, 2, true, empty, reach);
  const auto id = [&](int x, int y) {
    const size_t i = size_t(y) * w + x;
    return size_t(px[2 * i]) | size_t(px[2 * i + 1]) << 16;
  };
  const auto d2 = [&](size_t a, size_t b) {
    const long dx = long(a % size_t(w)) - long(b % size_t(w)), dy = long(a / size_t(w)) - long(b / size_t(w));
    return dx * dx + dy * dy;
  };
  std::vector<long> best(n, -1);
  for (size_t i = 0; i < n; ++i)
    for (size_t k = 0; k < n; ++k)
      if (!empty[k] && (best[i] < 0 || d2(i, k) < best[i])) best[i] = d2(i, k);
  const auto near = [&](int x, int y) { return double(best[size_t(y) * w + x]) <= reach * reach; };
  int first_near_row = -1, wholly_far_rows = 0, runs = 0;
  for (int y = 0; y < h; ++y) {
    int first = -1;
    for (int x = 0; x < w && first < 0; ++x)
      if (near(x, y)) first = x;
    if (first >= 0 && first_near_row < 0) first_near_row = y;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!empty[i]) {
        ASSERT_EQ(id(x, y), i) << "kept texel changed";
      } else if (near(x, y)) {
        ASSERT_FALSE(empty[id(x, y)]) << x << "," << y;
        ASSERT_EQ(d2(i, id(x, y)), best[i]) << x << "," << y;
      } else if (first >= 0) {
        ++runs;
        ASSERT_EQ(id(x, y), x < first ? id(first, y) : id(x - 1, y)) << x << "," << y;
      }
    }
    if (first < 0) {
      ++wholly_far_rows;
      const int from = y == 0 || first_near_row < 0 ? -1 : y - 1;
      for (int x = 0; x < w; ++x) {
        if (from >= 0) {
          ASSERT_EQ(id(x, y), id(x, from)) << x << "," << y;
        } else {
          ASSERT_FALSE(empty[id(x, y)]) << x << "," << y << ": a top row holds a kept texel's copy";
        }
      }
    }
  }
  EXPECT_GT(wholly_far_rows, 20);
  EXPECT_GT(runs, 100);
  // The top rows copy the first row with a near texel: check one column.
  for (int y = 0; y < first_near_row; ++y) EXPECT_EQ(id(7, y), id(7, first_near_row)) << y;
  EXPECT_NE(before, px);
}

// 8-bit RGB as the warp writes it: the copy is the whole texel; nothing
// kept gives zeros; bad sizes leave the pixels as they were.
TEST(AtlasFill, NearestFillCopiesWholeTexelsAndRefusesBadSizes) {
  std::vector<uint8_t> px(5 * 3 * 3, 0), empty(15, 1);
  empty[7] = 0;  // the centre texel, (2, 1)
  px[21] = 10, px[22] = 20, px[23] = 30;
  nearest_fill(px.data(), 5, 3, 3, false, empty);
  for (size_t i = 0; i < 15; ++i) {
    EXPECT_EQ(px[3 * i], 10) << i;
    EXPECT_EQ(px[3 * i + 1], 20) << i;
    EXPECT_EQ(px[3 * i + 2], 30) << i;
  }
  std::vector<uint8_t> none(4 * 4 * 3, 200);
  nearest_fill(none.data(), 4, 4, 3, false, std::vector<uint8_t>(16, 1));
  EXPECT_TRUE(std::all_of(none.begin(), none.end(), [](uint8_t v) { return v == 0; }));
  std::vector<uint8_t> keep(48, 9);
  const std::vector<uint8_t> before = keep;
  nearest_fill(keep.data(), 4, 4, 3, false, std::vector<uint8_t>(15, 1));  // mask too short
  nearest_fill(keep.data(), 0, 4, 3, false, {});
  nearest_fill(keep.data(), 4, 4, 9, false, std::vector<uint8_t>(16, 1));  // too many channels
  EXPECT_EQ(keep, before);
}

}  // namespace
}  // namespace gltfwarp
