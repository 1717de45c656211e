// Pull-push fill of an atlas's empty texels (see atlas_fill.h).
#include "codec/encode/texture/atlas_fill.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <OpenImageIO/parallel.h>

namespace gltfwarp {
namespace {

// One pyramid level: channel values (averages of the kept texels below) and
// whether any kept texel lies below each texel.
struct Level {
  int w = 0, h = 0;
  std::vector<float> value;    // w * h * channels
  std::vector<uint8_t> known;  // w * h
};

// Value i (texel * channels + channel) of 8-bit or 16-bit (deep) pixels.
double channel_value(const uint8_t* pixels, bool deep, size_t i) {
  return deep ? double(reinterpret_cast<const uint16_t*>(pixels)[i]) : double(pixels[i]);
}

// Stores q, already rounded and within the depth's range.
void store_channel(uint8_t* pixels, bool deep, size_t i, double q) {
  if (deep)
    reinterpret_cast<uint16_t*>(pixels)[i] = uint16_t(q);
  else
    pixels[i] = uint8_t(q);
}

}  // namespace

void pull_push_fill(uint8_t* pixels, int width, int height, int channels, bool deep,
                    std::span<const uint8_t> empty) {
  if (width <= 0 || height <= 0 || channels <= 0 || channels > 8 || empty.size() != size_t(width) * height)
    return;
  const int nch = channels;
  auto texel = [&](int x, int y, int c) -> float {
    return float(channel_value(pixels, deep, (size_t(y) * width + x) * nch + c));
  };
  // Pull: level 1 from the pixels, each further level from the one below,
  // down to a single texel. Each parent averages its kept children. Rows of
  // a level are independent (each writes its own texels), so they run on
  // every core: a 4096² source's reference fill is 16M texels.
  std::vector<Level> levels;
  for (int w = width, h = height; w > 1 || h > 1;) {
    Level next;
    next.w = (w + 1) / 2;
    next.h = (h + 1) / 2;
    next.value.assign(size_t(next.w) * next.h * nch, 0.0f);
    next.known.assign(size_t(next.w) * next.h, 0);
    const Level* below = levels.empty() ? nullptr : &levels.back();
    OIIO::parallel_for(0, next.h, [&](int y) {
      for (int x = 0; x < next.w; ++x) {
        float sum[8] = {};
        int n = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int cx = 2 * x + dx, cy = 2 * y + dy;
            if (cx >= w || cy >= h) continue;
            const size_t ci = size_t(cy) * w + cx;
            if (below ? !below->known[ci] : empty[ci] != 0) continue;
            for (int c = 0; c < nch; ++c) sum[c] += below ? below->value[ci * nch + c] : texel(cx, cy, c);
            ++n;
          }
        if (n == 0) continue;
        const size_t pi = size_t(y) * next.w + x;
        next.known[pi] = 1;
        for (int c = 0; c < nch; ++c) next.value[pi * nch + c] = sum[c] / float(n);
      }
    });
    w = next.w;
    h = next.h;
    levels.push_back(std::move(next));
  }
  if (levels.empty()) return;  // a single texel: nothing to fill from
  // Push: every unknown texel of a level takes the bilinear interpolation of
  // the (by then complete) level above, from the top down to the pixels.
  auto interpolate = [nch](const Level& up, double fx, double fy, float* out) {
    const double sx = std::clamp(fx, 0.0, double(up.w - 1)), sy = std::clamp(fy, 0.0, double(up.h - 1));
    const int x0 = int(sx), y0 = int(sy);
    const int x1 = std::min(x0 + 1, up.w - 1), y1 = std::min(y0 + 1, up.h - 1);
    const float ax = float(sx - x0), ay = float(sy - y0);
    for (int c = 0; c < nch; ++c) {
      auto at = [&](int x, int y) { return up.value[(size_t(y) * up.w + x) * nch + c]; };
      out[c] = (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) +
               (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
    }
  };
  if (!levels.back().known[0])  // nothing kept at all
    std::fill(levels.back().value.begin(), levels.back().value.end(), 0.0f);
  levels.back().known[0] = 1;
  for (size_t k = levels.size() - 1; k-- > 0;) {
    Level& lv = levels[k];
    const Level& up = levels[k + 1];
    OIIO::parallel_for(0, lv.h, [&](int y) {
      for (int x = 0; x < lv.w; ++x) {
        const size_t i = size_t(y) * lv.w + x;
        if (lv.known[i]) continue;
        interpolate(up, (x + 0.5) / 2.0 - 0.5, (y + 0.5) / 2.0 - 0.5, &lv.value[i * nch]);
        lv.known[i] = 1;
      }
    });
  }
  const Level& up = levels.front();
  const double top = deep ? 65535.0 : 255.0;
  OIIO::parallel_for(0, height, [&](int y) {
    float v[8];
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      if (!empty[i]) continue;
      interpolate(up, (x + 0.5) / 2.0 - 0.5, (y + 0.5) / 2.0 - 0.5, v);
      for (int c = 0; c < nch; ++c) {
        store_channel(pixels, deep, i * nch + c, std::round(std::clamp(double(v[c]), 0.0, top)));
      }
    }
  });
}

void nearest_fill(uint8_t* pixels, int width, int height, int channels, bool deep,
                  std::span<const uint8_t> empty, double max_distance) {
  if (width <= 0 || height <= 0 || channels <= 0 || channels > 8 || empty.size() != size_t(width) * height)
    return;
  const size_t texel_bytes = size_t(channels) * (deep ? 2 : 1);
  const auto at = [width](int x, int y) { return size_t(y) * size_t(width) + size_t(x); };
  if (std::all_of(empty.begin(), empty.end(), [](uint8_t e) { return e != 0; })) {
    std::fill(pixels, pixels + size_t(width) * height * texel_bytes, uint8_t(0));
    return;
  }
  std::vector<uint8_t> far(max_distance > 0 ? size_t(width) * height : 0, 0);
  // Pass 1, per column: the nearest kept row in that column (-1: none).
  std::vector<int32_t> kept_row(size_t(width) * height, -1);
  OIIO::parallel_for(0, width, [&](int x) {
    int last = -1;
    for (int y = 0; y < height; ++y) {
      if (!empty[at(x, y)]) last = y;
      kept_row[at(x, y)] = last;
    }
    last = -1;
    for (int y = height - 1; y >= 0; --y) {
      if (!empty[at(x, y)]) last = y;
      int32_t& r = kept_row[at(x, y)];
      if (last >= 0 && (r < 0 || last - y < y - r)) r = last;
    }
  });
  // Pass 2, per row: the lower envelope of the parabolas (x - q)^2 + f(q),
  // f(q) = the squared distance down column q to its nearest kept row; the
  // parabola lowest at x names the column of x's nearest kept texel. The
  // f values are integers below 2^33, exact in a double; an intersection is
  // a ratio with a denominator below 2^18, so where it is not an integer it
  // lies at least 2^-18 from every x, far beyond a double's rounding.
  OIIO::parallel_for(0, height, [&](int y) {
    std::vector<int> site(static_cast<size_t>(width));
    std::vector<double> from(static_cast<size_t>(width) + 1);
    const auto f = [&](int q) {
      const double d = double(y - kept_row[at(q, y)]);
      return d * d + double(q) * q;
    };
    int k = -1;
    for (int q = 0; q < width; ++q) {
      if (kept_row[at(q, y)] < 0) continue;  // a column with nothing kept
      double s = -HUGE_VAL;
      while (k >= 0) {
        s = (f(q) - f(site[size_t(k)])) / (2.0 * (q - site[size_t(k)]));
        if (s > from[size_t(k)]) break;
        --k;
      }
      if (k < 0) s = -HUGE_VAL;
      ++k;
      site[size_t(k)] = q;
      from[size_t(k)] = s;
    }
    int j = 0;
    for (int x = 0; x < width; ++x) {
      while (j < k && from[size_t(j) + 1] <= x) ++j;
      if (!empty[at(x, y)]) continue;
      const int q = site[size_t(j)];
      if (max_distance > 0) {
        const double dx = x - q, dy = y - kept_row[at(q, y)];
        if (dx * dx + dy * dy > max_distance * max_distance) {
          far[at(x, y)] = 1;
          continue;
        }
      }
      const uint8_t* src = pixels + at(q, kept_row[at(q, y)]) * texel_bytes;
      std::copy(src, src + texel_bytes, pixels + at(x, y) * texel_bytes);
    }
  });
  if (max_distance <= 0) return;
  // Beyond max_distance: runs along rows (atlas_fill.h).
  std::vector<uint8_t> whole(size_t(height), 0);
  OIIO::parallel_for(0, height, [&](int y) {
    int first = -1;
    for (int x = 0; x < width; ++x)
      if (!far[at(x, y)]) {
        first = x;
        break;
      }
    if (first < 0) {
      whole[size_t(y)] = 1;
      return;
    }
    for (int x = 0; x < width; ++x) {
      if (!far[at(x, y)]) continue;
      const int from = x == 0 || x < first ? first : x - 1;
      std::copy(pixels + at(from, y) * texel_bytes, pixels + at(from, y) * texel_bytes + texel_bytes,
                pixels + at(x, y) * texel_bytes);
    }
  });
  int lead = 0;
  while (lead < height && whole[size_t(lead)]) ++lead;
  for (int y = 0; y < height; ++y) {
    if (!whole[size_t(y)]) continue;
    const int from = y < lead ? lead : y - 1;
    std::copy(pixels + at(0, from) * texel_bytes,
              pixels + at(0, from) * texel_bytes + size_t(width) * texel_bytes,
              pixels + at(0, y) * texel_bytes);
  }
}

void flatten_empty_blocks(uint8_t* pixels, int width, int height, int channels, bool deep,
                          std::span<const uint8_t> empty, int block) {
  if (width <= 0 || height <= 0 || channels <= 0 || channels > 8 || block < 1 ||
      empty.size() != size_t(width) * height)
    return;
  const int nch = channels;
  const int rows = (height + block - 1) / block;
  // Each band of blocks writes only its own texels.
  OIIO::parallel_for(0, rows, [&](int band) {
    const int y0 = band * block, y1 = std::min(height, y0 + block);
    for (int x0 = 0; x0 < width; x0 += block) {
      const int x1 = std::min(width, x0 + block);
      bool all_empty = true;
      for (int y = y0; y < y1 && all_empty; ++y)
        for (int x = x0; x < x1; ++x)
          if (!empty[size_t(y) * width + x]) {
            all_empty = false;
            break;
          }
      if (!all_empty) continue;
      const double count = double(x1 - x0) * double(y1 - y0);
      for (int c = 0; c < nch; ++c) {
        double sum = 0;
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) sum += channel_value(pixels, deep, (size_t(y) * width + x) * nch + c);
        const double mean = std::round(sum / count);
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) store_channel(pixels, deep, (size_t(y) * width + x) * nch + c, mean);
      }
    }
  });
}

}  // namespace gltfwarp
