#include "codec/core/corner_match.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace gltfwarp {
namespace {

struct Grid {
  double cell;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (static_cast<uint64_t>(x) * 73856093ull) ^ (static_cast<uint64_t>(y) * 19349663ull) ^
           (static_cast<uint64_t>(z) * 83492791ull);
  }
  // Clamped, so huge coordinates over a tiny cell (or a NaN) cannot overflow
  // the integer cast; clamped points share the outermost cells, which only
  // costs time.
  int64_t coord(float v) const {
    const double q = std::floor(static_cast<double>(v) / cell);
    if (!(q == q)) return 0;
    constexpr double kLimit = 1152921504606846976.0;  // 2^60
    return static_cast<int64_t>(std::clamp(q, -kLimit, kLimit));
  }
};

double dist2(const float* a, const float* b) {
  const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

CornerMatch match_corners(const std::vector<float>& sp, const std::vector<uint32_t>& st,
                          const std::vector<float>& dp, const std::vector<uint32_t>& dt, double tolerance) {
  CornerMatch r;
  r.source_corner.assign(dt.size(), 0);
  const size_t sn = sp.size() / 3;
  const size_t sf = st.size() / 3;
  const size_t dn = dp.size() / 3;
  // Indices out of range: nothing can be matched safely.
  if (std::any_of(st.begin(), st.end(), [&](uint32_t v) { return v >= sn; }) ||
      std::any_of(dt.begin(), dt.end(), [&](uint32_t v) { return v >= dn; })) {
    r.unmatched_faces = dt.size() / 3;
    return r;
  }
  // Source vertex -> faces (CSR).
  std::vector<uint32_t> start(sn + 1, 0), faces(st.size());
  for (uint32_t v : st) start[v + 1]++;
  for (size_t i = 0; i < sn; ++i) start[i + 1] += start[i];
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t c = 0; c < st.size(); ++c) faces[fill[st[c]]++] = static_cast<uint32_t>(c / 3);

  // A non-finite tolerance (positions near the float range) degrades to one
  // cell: slow but exact.
  const double tol = std::isfinite(tolerance) ? std::max(tolerance, 1e-12) : 1e300;
  Grid grid{tol * 2, {}};
  grid.cells.reserve(sn);
  for (size_t v = 0; v < sn; ++v)
    grid.cells[Grid::key(grid.coord(sp[3 * v]), grid.coord(sp[3 * v + 1]), grid.coord(sp[3 * v + 2]))]
        .push_back(static_cast<uint32_t>(v));
  const double tol2 = tol * tol;
  std::vector<uint8_t> used(sf, 0);

  for (size_t f = 0; f < dt.size() / 3; ++f) {
    const float* d[3] = {&dp[3 * dt[3 * f]], &dp[3 * dt[3 * f + 1]], &dp[3 * dt[3 * f + 2]]};
    int64_t best_face = -1, best_rot = 0;
    double best_err = 1e300;
    bool best_unused = false;
    const int64_t cx = grid.coord(d[0][0]), cy = grid.coord(d[0][1]), cz = grid.coord(d[0][2]);
    for (int64_t ox = -1; ox <= 1; ++ox)
      for (int64_t oy = -1; oy <= 1; ++oy)
        for (int64_t oz = -1; oz <= 1; ++oz) {
          auto it = grid.cells.find(Grid::key(cx + ox, cy + oy, cz + oz));
          if (it == grid.cells.end()) continue;
          for (uint32_t s : it->second) {
            if (dist2(&sp[3 * s], d[0]) > tol2) continue;
            for (uint32_t i = start[s]; i < start[s + 1]; ++i) {
              const uint32_t F = faces[i];
              for (int rot = 0; rot < 3; ++rot) {
                if (st[3 * F + rot] != s) continue;
                const double e1 = dist2(&sp[3 * st[3 * F + (rot + 1) % 3]], d[1]);
                const double e2 = dist2(&sp[3 * st[3 * F + (rot + 2) % 3]], d[2]);
                if (e1 > tol2 || e2 > tol2) continue;
                const double err = dist2(&sp[3 * s], d[0]) + e1 + e2;
                const bool unused = !used[F];
                // Prefer faces not matched yet (duplicates), then the closest.
                if ((unused && !best_unused) || (unused == best_unused && err < best_err)) {
                  best_face = F;
                  best_rot = rot;
                  best_err = err;
                  best_unused = unused;
                }
              }
            }
          }
        }
    if (best_face < 0) {
      r.unmatched_faces++;
      for (int k = 0; k < 3; ++k) r.source_corner[3 * f + k] = 0;
      continue;
    }
    used[best_face] = 1;
    for (int k = 0; k < 3; ++k)
      r.source_corner[3 * f + k] = static_cast<uint32_t>(3 * best_face + (best_rot + k) % 3);
  }
  return r;
}

}  // namespace gltfwarp
