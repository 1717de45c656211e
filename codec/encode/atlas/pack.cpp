// Orientation and packing of patches into atlas pages (sources in pack.h).
#include "codec/encode/atlas/pack.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <functional>
#include <numeric>

#include "codec/core/geometry2d.h"
#include "codec/core/parallel.h"
#include "codec/encode/atlas/congruent_fit.h"
#include "codec/encode/atlas/texel_alignment.h"
#include "codec/encode/atlas/texel_density.h"
#include "format/bitstream/decode_uvs.h"

namespace gltfwarp {
namespace {

// The format's placement arithmetic (format/bitstream/uvmap.h): the packer rasterises
// exactly the footprint the decoder reproduces.
constexpr uint32_t kRotSteps = kRotationSteps;
void rot_cs(uint32_t code, double& c, double& s) { rotation_cos_sin(code, c, s); }
uint32_t rot_code(double radians) { return rotation_code_for(radians); }
double pscale(int32_t step) { return patch_scale(step); }

// ---- Patch footprints.

constexpr int kNone = INT_MIN;
constexpr double kEps = 1e-3;  // texels: margin against rounding between encoder and decoder

struct Mask {
  uint32_t code = 0;
  int bx0 = 0, by0 = 0;                   // texel origin of the mask in the rotated, scaled patch frame
  int cw = 0, ch = 0;                     // size in cells
  std::vector<int> bottom, top;           // per cell column: first occupied row, last + 1 (kNone: empty)
  std::vector<int> row_start;             // per cell row r: runs[row_start[r] .. row_start[r + 1])
  std::vector<std::pair<int, int>> runs;  // occupied cell columns [first, last + 1) of a row
  std::vector<int> widest;                // per cell row: its widest run
  uint64_t cells = 0;
  int step = 1;  // positions (in cells) on multiples of this: MIP blocks of an aligned patch
  int align_up(int v) const { return (v + step - 1) / step * step; }  // the first position >= v
};

struct PatchInfo {
  uint32_t prim = 0, patch = 0;
  std::vector<uint32_t> faces;
  uint32_t base_code = 0;
  int32_t scale_step = 0;  // per-patch scale code (format's patch_scale)
  Mask masks[4];
  int mask_count = 0;
  uint64_t order_key = 0;
  int32_t copy_of = -1;  // texel reuse: index of the original's PatchInfo (this one is not packed)
  SimilarityFit fit;     // copy's patch-local frame -> original's
  // Texel-exact (texel_alignment.h): the layout's similarity to its source
  // texels, when it has one, and whether this attempt's scale aligns it.
  SimilarityFit source_fit;
  double extent = 0;  // model units from the patch's origin to its farthest corner
  bool aligned = false;
  AlignedTransform aligned_at[4];  // per quarter turn of the source image
};

struct TriRaster {
  // Marks every texel whose square [i, i+1] x [j, j+1] meets the triangle
  // (conservative), grown by kEps.
  static void conservative(double ax, double ay, double bx, double by, double cx, double cy, int tw, int th,
                           std::vector<uint8_t>& bits) {
    double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (area < 0) {
      std::swap(bx, cx);
      std::swap(by, cy);
      area = -area;
    }
    const int i0 = std::max(0, int(std::floor(std::min({ax, bx, cx}) - kEps)));
    const int i1 = std::min(tw - 1, int(std::floor(std::max({ax, bx, cx}) + kEps)));
    const int j0 = std::max(0, int(std::floor(std::min({ay, by, cy}) - kEps)));
    const int j1 = std::min(th - 1, int(std::floor(std::max({ay, by, cy}) + kEps)));
    const double px[3] = {ax, bx, cx}, py[3] = {ay, by, cy};
    double ex[3], ey[3], slack[3];
    for (int e = 0; e < 3; ++e) {
      ex[e] = px[(e + 1) % 3] - px[e];
      ey[e] = py[(e + 1) % 3] - py[e];
      slack[e] = 0.5 * (std::abs(ex[e]) + std::abs(ey[e])) + kEps * std::hypot(ex[e], ey[e]);
    }
    const bool degenerate = !(area > 1e-12);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        bool in = true;
        if (!degenerate) {
          const double x = i + 0.5, y = j + 0.5;
          for (int e = 0; e < 3 && in; ++e) in = ex[e] * (y - py[e]) - ey[e] * (x - px[e]) + slack[e] >= 0;
        }
        if (in) bits[size_t(j) * tw + i] = 1;
      }
    }
  }
};

// Scratch buffers of build_mask, one set per worker.
struct MaskScratch {
  std::vector<double> q;
  std::vector<uint8_t> bits, tmp;
};

// Chebyshev dilation of a tw x th bit image by r, rows then columns. A cell is
// set when some set cell lies within r along the pass's axis: one sweep each
// way tracking the nearest set cell, so the cost does not grow with r.
void dilate_chebyshev(std::vector<uint8_t>& bits, int tw, int th, int r, std::vector<uint8_t>& tmp) {
  constexpr int kFar = INT_MIN / 2;
  tmp.assign(bits.size(), 0);
  for (int j = 0; j < th; ++j) {
    const uint8_t* row = &bits[size_t(j) * tw];
    uint8_t* out = &tmp[size_t(j) * tw];
    for (int i = 0, last = kFar; i < tw; ++i) {
      if (row[i]) last = i;
      out[i] = i - last <= r;
    }
    for (int i = tw - 1, next = -kFar; i >= 0; --i) {
      if (row[i]) next = i;
      out[i] |= next - i <= r;
    }
  }
  std::vector<int> nearest(size_t(tw), kFar);
  for (int j = 0; j < th; ++j) {
    const uint8_t* in = &tmp[size_t(j) * tw];
    uint8_t* out = &bits[size_t(j) * tw];
    for (int i = 0; i < tw; ++i) {
      if (in[i]) nearest[i] = j;
      out[i] = j - nearest[i] <= r;
    }
  }
  nearest.assign(size_t(tw), -kFar);
  for (int j = th - 1; j >= 0; --j) {
    const uint8_t* in = &tmp[size_t(j) * tw];
    uint8_t* out = &bits[size_t(j) * tw];
    for (int i = 0; i < tw; ++i) {
      if (in[i]) nearest[i] = j;
      out[i] |= nearest[i] - j <= r;
    }
  }
}

// The patch's footprint under texel = (sc, -ss; ss, sc) * p + (ox, oy), as
// apply_placements, (ox, oy) being the fraction of a texel a fine placement
// adds to the whole texels the packer chooses.
// block > 1 (an aligned patch's MIP blocks, mip_block_residue): the mask's
// origin moves back so that a position on multiples of the block (m.step
// cells) gives the whole-texel position that lines the blocks up.
void build_mask(const PackPrimitive& pr, const std::vector<uint32_t>& faces, double sc, double ss, double ox,
                double oy, int r, int cell, bool true_shape, const BlockResidue& residue, int block, Mask& m,
                std::vector<double>& q, std::vector<uint8_t>& bits, std::vector<uint8_t>& tmp) {
  q.resize(faces.size() * 6);
  double minx = 1e300, miny = 1e300, maxx = -1e300, maxy = -1e300;
  for (size_t k = 0; k < faces.size(); ++k) {
    for (int v = 0; v < 3; ++v) {
      const double x = pr.corner_xy[6 * size_t(faces[k]) + 2 * v];
      const double y = pr.corner_xy[6 * size_t(faces[k]) + 2 * v + 1];
      const double qx = (sc * x - ss * y) + ox, qy = (ss * x + sc * y) + oy;  // as apply_placements
      q[6 * k + 2 * v] = qx;
      q[6 * k + 2 * v + 1] = qy;
      minx = std::min(minx, qx), maxx = std::max(maxx, qx);
      miny = std::min(miny, qy), maxy = std::max(maxy, qy);
    }
  }
  const int fx0 = int(std::floor(minx - kEps)), fx1 = int(std::floor(maxx + kEps));
  const int fy0 = int(std::floor(miny - kEps)), fy1 = int(std::floor(maxy + kEps));
  // Whole position = cell * cx - bx0 = residue (mod block) when block divides cell * cx.
  const auto shift = [&](int start, int want) {
    return block > 1 ? ((start + want) % block + block) % block : 0;
  };
  const int lead_x = r + shift(fx0 - r, residue.x), lead_y = r + shift(fy0 - r, residue.y);
  m.bx0 = fx0 - lead_x;
  m.by0 = fy0 - lead_y;
  m.step = block > cell ? block / cell : 1;
  const int tw = fx1 - fx0 + 1 + lead_x + r, th = fy1 - fy0 + 1 + lead_y + r;
  bits.assign(size_t(tw) * th, 0);
  for (size_t k = 0; k < faces.size(); ++k)
    TriRaster::conservative(q[6 * k] - m.bx0, q[6 * k + 1] - m.by0, q[6 * k + 2] - m.bx0,
                            q[6 * k + 3] - m.by0, q[6 * k + 4] - m.bx0, q[6 * k + 5] - m.by0, tw, th, bits);
  if (!true_shape) std::fill(bits.begin(), bits.end(), 1);  // the bounding rectangle
  if (r > 0 && true_shape) dilate_chebyshev(bits, tw, th, r, tmp);
  m.cw = (tw + cell - 1) / cell;
  m.ch = (th + cell - 1) / cell;
  m.bottom.assign(m.cw, kNone);
  m.top.assign(m.cw, kNone);
  m.cells = 0;
  m.row_start.assign(1, 0);
  m.runs.clear();
  std::vector<uint8_t> cellrow(m.cw);
  for (int cj = 0; cj < m.ch; ++cj) {
    std::fill(cellrow.begin(), cellrow.end(), 0);
    for (int j = cj * cell; j < std::min(th, (cj + 1) * cell); ++j)
      for (int i = 0; i < tw; ++i)
        if (bits[size_t(j) * tw + i]) cellrow[i / cell] = 1;
    for (int ci = 0; ci < m.cw; ++ci) {
      if (!cellrow[ci]) continue;
      ++m.cells;
      if (m.bottom[ci] == kNone) m.bottom[ci] = cj;
      m.top[ci] = cj + 1;
      if (ci == 0 || !cellrow[ci - 1])
        m.runs.push_back({ci, ci + 1});
      else
        m.runs.back().second = ci + 1;
    }
    m.row_start.push_back(int(m.runs.size()));
  }
  m.widest.assign(m.ch, 0);
  for (int row = 0; row < m.ch; ++row)
    for (int k = m.row_start[row]; k < m.row_start[row + 1]; ++k)
      m.widest[row] = std::max(m.widest[row], m.runs[k].second - m.runs[k].first);
}

constexpr int kLongFree = 65535;  // Bitmap::free_from's cap: "this many or more"

// Occupancy of one page, one bit per cell, and per cell the length of the
// free run that starts there (0 where occupied), so that whether a run of
// a mask fits is one look-up.
struct Bitmap {
  int wc = 0, hc = 0, words = 0;
  std::vector<uint64_t> bits;
  std::vector<uint16_t> free_from;  // capped at kLongFree (16 bits: 2 bytes per cell)
  int used_rows = 0;                // rows below this are all free
  std::vector<int> max_free;        // per row: longest run of free cells
  void reset(int w, int h) {
    wc = w, hc = h, words = (w + 63) / 64, used_rows = 0;
    bits.assign(size_t(words) * h, 0);
    max_free.assign(h, w);
    free_from.resize(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) free_from[size_t(y) * w + x] = uint16_t(std::min(w - x, kLongFree));
  }
  // Free cells from x on in row y (kLongFree: that many or more).
  int free_at(int y, int x) const { return free_from[size_t(y) * wc + x]; }
  void update_free(int y) {
    const uint64_t* row = &bits[size_t(y) * words];
    int best = 0, run = 0;
    for (int w = 0; w < words; ++w) {
      const uint64_t v = row[w];
      const int nbits = std::min(64, wc - (w << 6));
      if (v == 0) {
        run += nbits;
        continue;
      }
      for (int b = 0; b < nbits; ++b) {
        if (v >> b & 1) {
          best = std::max(best, run);
          run = 0;
        } else {
          ++run;
        }
      }
    }
    max_free[y] = std::max(best, run);
  }
  // First set bit in [lo, hi) of row y, or -1.
  int first_set(int y, int lo, int hi) const {
    const uint64_t* row = &bits[size_t(y) * words];
    int w = lo >> 6;
    const int wend = (hi - 1) >> 6;
    uint64_t v = row[w] & (~uint64_t(0) << (lo & 63));
    for (;;) {
      if (w == wend) {
        const int top = hi - (w << 6);
        if (top < 64) v &= (uint64_t(1) << top) - 1;
        return v ? (w << 6) + __builtin_ctzll(v) : -1;
      }
      if (v) return (w << 6) + __builtin_ctzll(v);
      v = row[++w];
    }
  }
  // First clear bit at or after `from` in row y (wc if none).
  int first_clear(int y, int from) const {
    const uint64_t* row = &bits[size_t(y) * words];
    int w = from >> 6;
    if (w >= words) return wc;
    uint64_t v = ~row[w] & (~uint64_t(0) << (from & 63));
    while (!v) {
      if (++w >= words) return wc;
      v = ~row[w];
    }
    return std::min(wc, (w << 6) + __builtin_ctzll(v));
  }
  void set(int y, int lo, int hi) {
    uint64_t* row = &bits[size_t(y) * words];
    for (int i = lo; i < hi; ++i) row[i >> 6] |= uint64_t(1) << (i & 63);
    uint16_t* run = &free_from[size_t(y) * wc];
    std::fill(run + lo, run + hi, uint16_t(0));
    for (int i = lo - 1; i >= 0 && run[i] != 0; --i) run[i] = uint16_t(std::min(lo - i, kLongFree));
  }
};

// Lowest (then leftmost) position where mask m fits, or false.
bool lowest_fit(const Bitmap& bm, const Mask& m, int& out_x, int& out_y, int y_from, int y_limit) {
  if (m.cw > bm.wc) return false;
  for (int y = m.align_up(y_from); y + m.ch <= bm.hc && y < y_limit; y += m.step) {
    if (y >= bm.used_rows) {  // everything below is free
      out_x = 0, out_y = y;
      return true;
    }
    bool room = true;  // every row has a free run as wide as the mask's row needs
    for (int r = 0; r < m.ch && room; ++r) room = bm.max_free[y + r] >= m.widest[r];
    if (!room) continue;
    int x = 0;
    int last = 0;  // the row that collided last is the likeliest to collide again
    while (x + m.cw <= bm.wc) {
      bool hit = false;
      for (int i = -1; i < m.ch && !hit; ++i) {
        const int r = i < 0 ? last : i;
        if (i == last) continue;
        const int yy = y + r;
        if (yy >= bm.used_rows) continue;
        for (int k = m.row_start[r]; k < m.row_start[r + 1]; ++k) {
          // p: the first occupied cell the run meets, if any.
          const int from = x + m.runs[k].first, to = x + m.runs[k].second, free = bm.free_at(yy, from);
          const int p = free == kLongFree ? bm.first_set(yy, from, to) : from + free < to ? from + free : -1;
          if (p >= 0) {  // skip the whole occupied run that starts at p
            x = m.align_up(std::max(x + 1, bm.first_clear(yy, p) - m.runs[k].first));
            hit = true;
            last = r;
            break;
          }
        }
      }
      if (!hit) {
        out_x = x, out_y = y;
        return true;
      }
    }
  }
  return false;
}

struct Placed {
  int page = -1, mask = 0, cx = 0, cy = 0;
};

struct Page {
  std::vector<int> sky;
};

// Whether a trial can still win, from its pages so far and their highest
// cell row: both only grow as patches are added, so once the area they
// already imply exceeds the smallest area a finished trial reached, the
// trial stops (pack_atlas). May be empty: every trial runs to its end.
using TrialHopeless = std::function<bool(size_t pages, int top_cells)>;

// Drops every patch (in order) onto the lowest-waste skyline position of the
// first page where it fits. Returns false when max_pages would be exceeded.
bool skyline_pack(const std::vector<PatchInfo>& patches, const std::vector<uint32_t>& order, int wc,
                  int hc_max, uint32_t max_pages, const TrialHopeless& hopeless, std::vector<Placed>& placed,
                  std::vector<Page>& pages) {
  int top_cells = 0;
  pages.clear();
  placed.assign(patches.size(), Placed{});
  for (uint32_t pi : order) {
    const PatchInfo& p = patches[pi];
    bool done = false;
    for (size_t pg = 0; pg <= pages.size() && !done; ++pg) {
      if (pg == pages.size()) {
        if (pages.size() >= max_pages) return false;
        pages.push_back(Page{std::vector<int>(wc, 0)});
      }
      std::vector<int>& sky = pages[pg].sky;
      long long best_score = LLONG_MAX;
      int best_m = -1, best_x = 0, best_y = 0;
      for (int mi = 0; mi < p.mask_count; ++mi) {
        const Mask& m = p.masks[mi];
        if (m.cw > wc || m.ch > hc_max) continue;
        for (int x = 0; x + m.cw <= wc; x += m.step) {
          int y = 0;
          for (int c = 0; c < m.cw; ++c)
            if (m.bottom[c] != kNone) y = std::max(y, sky[x + c] - m.bottom[c]);
          y = m.align_up(y);
          if (y + m.ch > hc_max || (long long)y * m.cw >= best_score) continue;
          long long waste = 0;
          int top = 0;
          for (int c = 0; c < m.cw; ++c)
            if (m.bottom[c] != kNone) {
              waste += y + m.bottom[c] - sky[x + c];
              top = std::max(top, y + m.top[c]);
            }
          const long long score = waste * 4 + (long long)top * m.cw;
          if (score < best_score) best_score = score, best_m = mi, best_x = x, best_y = y;
        }
      }
      if (best_m < 0) {
        if (std::all_of(sky.begin(), sky.end(), [](int v) { return v == 0; })) return false;
        continue;  // full: try the next page
      }
      const Mask& m = p.masks[best_m];
      for (int c = 0; c < m.cw; ++c)
        if (m.bottom[c] != kNone) {
          sky[best_x + c] = best_y + m.top[c];
          top_cells = std::max(top_cells, sky[best_x + c]);
        }
      placed[pi] = Placed{int(pg), best_m, best_x, best_y};
      done = true;
    }
    if (!done || (hopeless && hopeless(pages.size(), top_cells))) return false;
  }
  return true;
}

// Bottom-left-fill on a cell bitmap: every patch goes to the lowest, then
// leftmost, position (over its turns) where its true footprint fits, so small
// patches fill the holes that larger ones leave.
bool bitmap_pack(const std::vector<PatchInfo>& patches, const std::vector<uint32_t>& order, int wc,
                 int hc_max, uint32_t max_pages, int search_depth, const TrialHopeless& hopeless,
                 std::vector<Placed>& placed, std::vector<Page>& pages) {
  int top_cells = 0;
  std::vector<Bitmap> maps;
  pages.clear();
  placed.assign(patches.size(), Placed{});
  for (uint32_t pi : order) {
    const PatchInfo& p = patches[pi];
    bool done = false;
    for (size_t pg = 0; pg <= maps.size() && !done; ++pg) {
      if (pg == maps.size()) {
        if (maps.size() >= max_pages) return false;
        maps.emplace_back();
        maps.back().reset(wc, hc_max);
        pages.push_back(Page{std::vector<int>(wc, 0)});
      }
      Bitmap& bm = maps[pg];
      int best_m = -1, best_x = 0, best_y = 0, best_bottom = INT_MAX;
      // Holes far below the lowest point of the skyline are left alone: the
      // search starts a few patch heights above it (bounded work per patch).
      const int min_sky = *std::min_element(pages[pg].sky.begin(), pages[pg].sky.end());
      for (int mi = 0; mi < p.mask_count; ++mi) {
        const Mask& m = p.masks[mi];
        int x, y;
        // A turn can only win if it ends higher than the best so far.
        const int y_from = std::max(0, min_sky - search_depth * m.ch);
        if (!lowest_fit(bm, m, x, y, y_from, best_m < 0 ? INT_MAX : best_bottom - m.ch + 1)) continue;
        const int bottom = y + m.ch;
        if (bottom < best_bottom || (bottom == best_bottom && y < best_y)) {
          best_m = mi, best_x = x, best_y = y, best_bottom = bottom;
        }
      }
      if (best_m < 0) {
        if (bm.used_rows == 0) return false;  // does not fit an empty page
        continue;
      }
      const Mask& m = p.masks[best_m];
      for (int r = 0; r < m.ch; ++r) {
        for (int k = m.row_start[r]; k < m.row_start[r + 1]; ++k)
          bm.set(best_y + r, best_x + m.runs[k].first, best_x + m.runs[k].second);
        bm.update_free(best_y + r);
      }
      bm.used_rows = std::max(bm.used_rows, best_y + m.ch);
      std::vector<int>& sky = pages[pg].sky;
      for (int c = 0; c < m.cw; ++c)
        if (m.bottom[c] != kNone) {
          sky[best_x + c] = std::max(sky[best_x + c], best_y + m.top[c]);
          top_cells = std::max(top_cells, sky[best_x + c]);
        }
      placed[pi] = Placed{int(pg), best_m, best_x, best_y};
      done = true;
    }
    if (!done || (hopeless && hopeless(pages.size(), top_cells))) return false;
  }
  return true;
}

// v rounded up by `r`. A side that fits within `max_size` stays within it,
// rounded or not: a --max-atlas-size that is no multiple of 16 is the
// user's bound, and a patch set that fits it must not be shrunk for the
// rounding's sake.
uint32_t round_size(uint64_t v, SizeRounding r, uint32_t max_size) {
  if (v == 0) v = 1;
  uint64_t rounded = 1;
  if (r == SizeRounding::power_of_two)
    while (rounded < v) rounded <<= 1;
  else
    rounded = (v + kMipExactBlock - 1) / kMipExactBlock * kMipExactBlock;
  if (v <= max_size) rounded = std::min<uint64_t>(rounded, max_size);
  return uint32_t(std::min<uint64_t>(rounded, UINT32_MAX));
}

// The turn that lays the source image's axes along the atlas's: each face's
// gradients of the source u and v in the patch's layout give the directions
// the source's columns and rows run in; their angles, taken modulo 90
// degrees (as 4x angles, weighted by the face's layout area), average to
// the patch's. False where no face has a usable gradient.
bool source_axes_angle(const PackPrimitive& pr, std::span<const uint32_t> faces, double& angle) {
  if (pr.source_uv.size() != pr.corner_xy.size()) return false;
  double sum_c = 0, sum_s = 0;
  for (uint32_t f : faces) {
    double j[4];  // rows: the gradients of u and of v
    if (!layout_to_source_jacobian(pr.corner_xy, pr.source_uv, f, 1.0, 1.0, j)) continue;
    const double w = 2 * layout_face_area(pr.corner_xy, f);
    for (int t = 0; t < 2; ++t) {  // u, then v
      const double gx = j[2 * t], gy = j[2 * t + 1];
      if (!(std::hypot(gx, gy) > 0)) continue;
      const double phi = std::atan2(gy, gx);
      sum_c += w * std::cos(4 * phi), sum_s += w * std::sin(4 * phi);
    }
  }
  if (!std::isfinite(sum_c + sum_s) || (sum_c == 0 && sum_s == 0)) return false;
  angle = -std::atan2(sum_s, sum_c) / 4;  // turning by it takes the mean direction to a multiple of 90
  return true;
}

}  // namespace

const char* to_string(PackStatus s) {
  switch (s) {
    case PackStatus::ok:
      return "ok";
    case PackStatus::bad_input:
      return "bad input";
    case PackStatus::too_large:
      return "atlas too large even after shrinking";
  }
  return "unknown";
}

void placed_corner_texels(std::span<const double> corner_xy, const UvMap& map,
                          std::vector<double>& corner_texel) {
  const size_t nf = map.patch_of_face.size();
  corner_texel.resize(nf * 6);
  for (size_t f = 0; f < nf; ++f) {
    const PatchPlacement& pl = map.placements[map.patch_of_face[f]];
    for (int v = 0; v < 3; ++v)  // the decoder's arithmetic, fine placements (1.3) included
      placement_texel(map, pl, corner_xy[6 * f + 2 * v], corner_xy[6 * f + 2 * v + 1],
                      corner_texel[6 * f + 2 * v], corner_texel[6 * f + 2 * v + 1]);
  }
}

void measure_atlas(std::span<const PackPrimitive> prims, std::span<const UvMap> maps, PackReport& report) {
  report.covered_texels = report.overlap_texels = report.outside_texels = 0;
  if (maps.empty()) return;
  const uint32_t w = maps[0].atlas_width, h = maps[0].atlas_height;
  uint32_t pages = 0;
  for (const UvMap& m : maps) pages = std::max(pages, m.page_count);
  report.atlas_texels = uint64_t(w) * h * pages;
  // The decoder's own UVs (apply_placements), back in texels.
  std::vector<std::vector<double>> texels(prims.size());
  std::vector<float> uv;
  for (size_t i = 0; i < prims.size(); ++i) {
    if (apply_placements(prims[i].corner_xy, maps[i], uv) != UvStatus::ok) {
      placed_corner_texels(prims[i].corner_xy, maps[i], texels[i]);
      continue;
    }
    texels[i].resize(uv.size());
    for (size_t k = 0; k < uv.size(); k += 2) {
      texels[i][k] = double(uv[k]) * w;
      texels[i][k + 1] = double(uv[k + 1]) * h;
    }
  }
  std::vector<uint32_t> owner(size_t(w) * h);
  for (uint32_t page = 0; page < pages; ++page) {
    std::fill(owner.begin(), owner.end(), 0);
    uint32_t base = 0;
    for (size_t i = 0; i < prims.size(); ++i) {
      const UvMap& m = maps[i];
      const std::vector<double>& t = texels[i];
      for (size_t f = 0; f < m.patch_of_face.size(); ++f) {
        const uint32_t patch = m.patch_of_face[f];
        if (m.placements[patch].page != page) continue;
        // A copy on its original's texels is that patch, as far as overlap goes.
        const auto& reuse = prims[i].reuse_of;
        const bool copy = m.placements[patch].fine && patch < reuse.size() && reuse[patch] >= 0;
        const uint32_t id = base + (copy ? uint32_t(reuse[patch]) : patch) + 1;
        double ax = t[6 * f], ay = t[6 * f + 1], bx = t[6 * f + 2], by = t[6 * f + 3];
        double cx = t[6 * f + 4], cy = t[6 * f + 5];
        double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        if (area == 0) continue;
        if (area < 0) std::swap(bx, cx), std::swap(by, cy);
        const long long i0 = (long long)std::ceil(std::min({ax, bx, cx}) - 0.5);
        const long long i1 = (long long)std::floor(std::max({ax, bx, cx}) - 0.5);
        const long long j0 = (long long)std::ceil(std::min({ay, by, cy}) - 0.5);
        const long long j1 = (long long)std::floor(std::max({ay, by, cy}) - 0.5);
        for (long long j = j0; j <= j1; ++j)
          for (long long ix = i0; ix <= i1; ++ix) {
            const double x = double(ix) + 0.5, y = double(j) + 0.5;
            if ((bx - ax) * (y - ay) - (by - ay) * (x - ax) < 0) continue;
            if ((cx - bx) * (y - by) - (cy - by) * (x - bx) < 0) continue;
            if ((ax - cx) * (y - cy) - (ay - cy) * (x - cx) < 0) continue;
            if (ix < 0 || j < 0 || ix >= (long long)w || j >= (long long)h) {
              ++report.outside_texels;
              continue;
            }
            uint32_t& o = owner[size_t(j) * w + size_t(ix)];
            if (o == 0) {
              o = id;
              ++report.covered_texels;
            } else if (o != id) {
              ++report.overlap_texels;
            }
          }
      }
      base += m.patch_count;
    }
  }
  report.fill = report.atlas_texels ? double(report.covered_texels) / double(report.atlas_texels) : 0;
}

PackStatus pack_atlas(std::span<const PackPrimitive> prims, const PackOptions& options, PackResult& result) {
  const auto t0 = std::chrono::steady_clock::now();
  result = PackResult{};
  if (!(options.texel_scale > 0) || options.max_atlas_size < 4) return PackStatus::bad_input;
  std::vector<PatchInfo> patches;
  std::vector<uint32_t> base(prims.size(), 0);
  for (size_t i = 0; i < prims.size(); ++i) {
    const PackPrimitive& pr = prims[i];
    if (!pr.mesh) return PackStatus::bad_input;
    const uint32_t nf = pr.mesh->face_count();
    if (pr.patch_of_face.size() != nf || pr.corner_xy.size() != size_t(6) * nf) return PackStatus::bad_input;
    if (!pr.face_density.empty() && pr.face_density.size() != nf) return PackStatus::bad_input;
    base[i] = uint32_t(patches.size());
    for (uint32_t p = 0; p < pr.patch_count; ++p) {
      PatchInfo info;
      info.prim = uint32_t(i);
      info.patch = p;
      patches.push_back(std::move(info));
    }
    for (uint32_t f = 0; f < nf; ++f) {
      if (pr.patch_of_face[f] >= pr.patch_count) return PackStatus::bad_input;
      patches[base[i] + pr.patch_of_face[f]].faces.push_back(f);
    }
  }
  // Orientation: the source's axes (PatchOrientation), or else the
  // minimal-area rectangle of each patch's hull, quantized.
  std::vector<Vec2> pts;
  for (PatchInfo& p : patches) {
    const PackPrimitive& pr = prims[p.prim];
    double angle = 0;
    if (options.orientation == PatchOrientation::source_axes && source_axes_angle(pr, p.faces, angle)) {
      p.base_code = rot_code(angle);
      continue;
    }
    pts.clear();
    for (uint32_t f : p.faces)
      for (int v = 0; v < 3; ++v)
        pts.push_back(Vec2{pr.corner_xy[6 * size_t(f) + 2 * v], pr.corner_xy[6 * size_t(f) + 2 * v + 1]});
    const std::vector<Vec2> hull = convex_hull(pts);
    const OrientedRect rect = min_area_rect(hull);
    // Rotating by -angle makes the rectangle axis-aligned; check both signs
    // against the quantized table so a convention slip costs nothing.
    double best = 1e300;
    for (double a : {-rect.angle, rect.angle}) {
      const uint32_t code = rot_code(a);
      double c, s;
      rot_cs(code, c, s);
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (const Vec2& h : hull) {
        const double x = c * h.x - s * h.y, y = s * h.x + c * h.y;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
      const double area = (x1 - x0) * (y1 - y0);
      if (area < best) best = area, p.base_code = code;
    }
  }
  // Per-patch scale from the source's own density: each patch gets its
  // faces' density (an area-weighted quantile, or the texel-count preserving
  // RMS mean) over a reference density, quantized to the format's scale steps.
  std::vector<double> patch_w(patches.size(), 0), patch_d(patches.size(), 0);
  double all_w = 0, all_d2 = 0;
  for (size_t i = 0; i < prims.size(); ++i) {
    const PackPrimitive& pr = prims[i];
    if (pr.face_density.empty() || !options.per_patch_scale) continue;
    const auto dens = patch_densities(pr.corner_xy, pr.patch_of_face, pr.patch_count, pr.face_density,
                                      options.density_quantile);
    for (uint32_t p = 0; p < pr.patch_count; ++p) {
      if (!(dens[p].area > 0)) continue;
      patch_w[base[i] + p] = dens[p].area;
      patch_d[base[i] + p] = dens[p].density;
      all_w += dens[p].area, all_d2 += dens[p].squared;
    }
  }
  if (all_w > 0 && all_d2 > 0) {
    const double reference =
        options.density_reference > 0 ? options.density_reference : std::sqrt(all_d2 / all_w);
    for (size_t pi = 0; pi < patches.size(); ++pi) {
      if (!(patch_w[pi] > 0)) continue;
      const double ratio = patch_d[pi] / reference;
      const int32_t step = ratio > 0 ? scale_step_for(ratio) : kMinScaleStep;
      patches[pi].scale_step = std::clamp(step, options.min_scale_step, options.max_scale_step);
    }
  }
  for (PatchInfo& p : patches) {
    const auto& bias = prims[p.prim].scale_step_bias;
    if (p.patch < bias.size())
      p.scale_step = std::clamp(p.scale_step + bias[p.patch], options.min_scale_step, options.max_scale_step);
  }
  // Texel reuse: a copy whose replay matches its original's (to
  // max_reuse_residual texels) follows it instead of being packed.
  for (size_t i = 0; i < prims.size(); ++i) {
    const PackPrimitive& pr = prims[i];
    if (pr.reuse_of.size() != pr.patch_count || pr.twin_corner.size() != pr.corner_xy.size() / 2) continue;
    std::vector<double> from, to;
    for (uint32_t p = 0; p < pr.patch_count; ++p) {
      const int32_t o = pr.reuse_of[p];
      if (o < 0 || uint32_t(o) >= pr.patch_count || pr.reuse_of[size_t(o)] >= 0) continue;
      PatchInfo& copy = patches[base[i] + p];
      const PatchInfo& original = patches[base[i] + uint32_t(o)];
      from.clear(), to.clear();
      bool whole = true;
      for (uint32_t f : copy.faces)
        for (int v = 0; v < 3; ++v) {
          const uint32_t twin = pr.twin_corner[3 * size_t(f) + v];
          if (twin >= pr.twin_corner.size()) {
            whole = false;
            continue;
          }
          from.push_back(pr.corner_xy[6 * size_t(f) + 2 * v]),
              from.push_back(pr.corner_xy[6 * size_t(f) + 2 * v + 1]);
          to.push_back(pr.corner_xy[2 * size_t(twin)]), to.push_back(pr.corner_xy[2 * size_t(twin) + 1]);
        }
      if (!whole) continue;
      const SimilarityFit fit = fit_similarity(from, to);
      const double texels = options.texel_scale * pscale(original.scale_step);
      if (!fit.ok || !(fit.max_residual * texels <= options.max_reuse_residual) ||
          std::abs(std::hypot(fit.a, fit.b) - 1) > 0.05)
        continue;
      copy.copy_of = int32_t(base[i] + uint32_t(o));
      copy.fit = fit;
      copy.scale_step = original.scale_step;
    }
  }
  // Texel-exact patches: the layout's similarity to the source's texels
  // (an original of a copy stays coarse: copy_placement builds on it).
  if (options.align_texels) {
    std::vector<uint8_t> has_copy(patches.size(), 0);
    for (const PatchInfo& p : patches)
      if (p.copy_of >= 0) has_copy[size_t(p.copy_of)] = 1;
    run_in_parallel(patches.size(), worker_count(patches.size()), [&](size_t pi, size_t) {
      PatchInfo& p = patches[pi];
      const PackPrimitive& pr = prims[p.prim];
      if (p.copy_of >= 0 || has_copy[pi] || pr.align_width == 0 || pr.align_height == 0) return;
      p.source_fit = fit_texel_alignment(pr.corner_xy, pr.source_uv, p.faces, pr.align_width, pr.align_height,
                                         options.max_align_residual);
      if (!p.source_fit.ok) return;
      for (uint32_t f : p.faces)
        for (int v = 0; v < 3; ++v)
          p.extent = std::max(p.extent, std::hypot(pr.corner_xy[6 * size_t(f) + 2 * v],
                                                   pr.corner_xy[6 * size_t(f) + 2 * v + 1]));
    });
  }
  const int r = int((options.gutter + 1) / 2);
  const int block = int(std::max<uint32_t>(1, options.align_mip_block));
  double scale = double(float(options.texel_scale));
  const uint32_t max_size = options.max_atlas_size;
  for (uint32_t attempt = 0; attempt <= options.max_retries; ++attempt) {
    // Rough footprint at this scale (triangle area plus the dilated bounding
    // box rim), to choose the cell and to shrink early.
    int cell = int(options.cell);
    // Aligned at this scale: asked for at least min_align_density of the
    // source's density (fewer texels stay a resampling).
    for (PatchInfo& p : patches) {
      p.aligned = false;
      if (!p.source_fit.ok) continue;
      const double asked = scale * pscale(p.scale_step), density = std::hypot(p.source_fit.a, p.source_fit.b);
      if (!(asked >= options.min_align_density * density)) continue;
      p.aligned = true;
      for (int k = 0; k < 4 && p.aligned; ++k)
        p.aligned = aligned_transform(p.source_fit, k, scale, p.extent, p.aligned_at[k]);
    }
    double texel_area = 0;
    for (const PatchInfo& p : patches) {
      if (p.copy_of >= 0) continue;
      const PackPrimitive& pr = prims[p.prim];
      double area = 0, x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (uint32_t f : p.faces) {
        const double* c = &pr.corner_xy[6 * size_t(f)];
        area += layout_face_area(pr.corner_xy, f);
        for (int v = 0; v < 3; ++v) {
          x0 = std::min(x0, c[2 * v]), x1 = std::max(x1, c[2 * v]);
          y0 = std::min(y0, c[2 * v + 1]), y1 = std::max(y1, c[2 * v + 1]);
        }
      }
      const double ps = p.aligned ? std::hypot(p.source_fit.a, p.source_fit.b) : scale * pscale(p.scale_step);
      texel_area += area * ps * ps + (x1 - x0 + y1 - y0) * ps * (2 * r + 1) + 4.0 * r * r;
    }
    const double cap = double(max_size) * max_size * options.max_pages;
    if (texel_area > 0.9 * cap) {
      // Far too large (a scale floored by auto_texel_scale on a model of
      // 1e30 units): straight to the footprint that fits, not by halves,
      // which 60 retries cannot carry past a factor of 2^-60.
      scale = double(
          float(scale * std::max(1e-12, std::min(options.shrink_factor, std::sqrt(0.8 * cap / texel_area)))));
      ++result.report.shrink_retries;
      continue;
    }
    if (cell <= 0) {
      const double side = std::sqrt(texel_area / 0.8);
      cell = side <= 640 ? 1 : side <= 2560 ? 2 : 4;
    }
    // Each patch writes only its own masks, so they are built side by side.
    std::vector<MaskScratch> scratch(worker_count(patches.size()));
    run_in_parallel(patches.size(), scratch.size(), [&](size_t pi, size_t worker) {
      PatchInfo& p = patches[pi];
      if (p.copy_of >= 0) return;
      MaskScratch& sc = scratch[worker];
      p.mask_count = options.rotate_90 ? 4 : 1;
      for (int k = 0; k < p.mask_count; ++k) {
        Mask& m = p.masks[k];
        const AlignedTransform& at = p.aligned_at[k];
        if (p.aligned && !at.coarse) {
          m.code = 0;  // a fine placement writes rotation 0
          const double unit = scale * pscale(at.scale_step);
          const double fc = unit * (double(at.cos_q) * 0x1p-15), fs = unit * (double(at.sin_q) * 0x1p-15);
          build_mask(prims[p.prim], p.faces, fc, fs, at.frac_x, at.frac_y, r, cell, options.true_shapes,
                     mip_block_residue(p.source_fit, fc, fs, at.frac_x, at.frac_y, block), block, m, sc.q,
                     sc.bits, sc.tmp);
          continue;
        }
        // A coarse placement: the patch's own turn and step, or the aligned ones.
        m.code = p.aligned ? at.rotation : (p.base_code + uint32_t(k) * (kRotSteps / 4)) % kRotSteps;
        double c, s;
        rot_cs(m.code, c, s);
        const double unit = scale * pscale(p.aligned ? at.scale_step : p.scale_step);
        const int b = p.aligned ? block : 1;
        build_mask(prims[p.prim], p.faces, unit * c, unit * s, 0, 0, r, cell, options.true_shapes,
                   mip_block_residue(p.source_fit, unit * c, unit * s, 0, 0, b), b, m, sc.q, sc.bits, sc.tmp);
      }
    });
    uint64_t cell_area = 0;
    for (PatchInfo& p : patches) {
      if (p.copy_of >= 0) continue;
      cell_area += p.masks[0].cells;
      p.order_key = uint64_t(std::max(p.masks[0].ch, p.masks[0].cw)) << 32 | p.masks[0].cells;
    }
    std::vector<uint32_t> order;  // the patches packed: every one but the copies
    for (uint32_t pi = 0; pi < patches.size(); ++pi)
      if (patches[pi].copy_of < 0) order.push_back(pi);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return patches[a].order_key > patches[b].order_key; });
    const int hc_max = int(max_size) / cell;
    // Candidate page widths around the square that would hold the patches at 80%.
    std::vector<uint32_t> widths;
    const double side = std::sqrt(double(cell_area) / 0.8) * cell;
    int min_w = 0;  // narrowest page every patch fits in some turn of
    for (PatchInfo& p : patches) {
      if (p.copy_of >= 0) continue;
      int m = INT_MAX;
      for (int k = 0; k < p.mask_count; ++k) m = std::min(m, p.masks[k].cw);
      min_w = std::max(min_w, m * cell);
    }
    for (double f : {0.8, 0.9, 1.0, 1.12, 1.25, 1.45}) {
      uint32_t w = round_size(uint64_t(std::max(double(min_w), side * f)), options.rounding, max_size);
      w = std::min(w, max_size);
      if (std::find(widths.begin(), widths.end(), w) == widths.end()) widths.push_back(w);
    }
    if (options.max_pages > 1 && std::find(widths.begin(), widths.end(), max_size) == widths.end())
      widths.push_back(max_size);
    // Every (order, width) trial is independent: they run side by side, and
    // the best is chosen in trial order, so the result does not depend on
    // the thread count.
    std::vector<std::vector<uint32_t>> orders = {order};
    // Small sets: other orders (by area, by height) often interlock better.
    if (patches.size() <= options.multi_order_max_patches) {
      for (int variant = 0; variant < 2; ++variant) {
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
          const Mask& ma = patches[a].masks[0];
          const Mask& mb = patches[b].masks[0];
          return variant == 0 ? ma.cells > mb.cells : std::min(ma.ch, ma.cw) > std::min(mb.ch, mb.cw);
        });
        orders.push_back(order);
      }
    }
    struct Trial {
      const std::vector<uint32_t>* order = nullptr;
      uint32_t w = 0, h = 0, pages = 0;
      uint64_t area = UINT64_MAX;
      std::vector<Placed> placed;
    };
    std::vector<Trial> trials;
    for (const auto& o : orders)
      for (uint32_t w : widths) {
        trials.emplace_back();
        trials.back().order = &o;
        trials.back().w = w;
      }
    // The smallest area a finished trial reached. A trial whose pages so
    // far already imply a larger one stops: it cannot win, since the
    // choice below takes the smallest area (ties go to the squarer, then
    // the earlier trial, and a tie never stops). Which trials stop depends
    // on timing; the winner does not. The CesiumMilkTruck's trials ran to
    // their end for nothing in most of its packs.
    std::atomic<uint64_t> finished_best{UINT64_MAX};
    std::atomic<uint32_t> stopped{0};
    // A page's height from its highest cell row, as the chosen trial's is
    // rounded: the bound and the result use this one rule, which is what
    // makes the bound a bound.
    const auto page_height = [&](int top_cells) {
      return round_size(uint64_t(top_cells) * cell, options.rounding, max_size);
    };
    auto run_trial = [&](Trial& t) {
      const int wc = int(t.w) / cell;
      TrialHopeless hopeless;
      if (options.stop_losing_trials)
        hopeless = [&](size_t pages, int top_cells) {
          const bool lost =
              uint64_t(t.w) * page_height(top_cells) * pages > finished_best.load(std::memory_order_relaxed);
          if (lost) stopped.fetch_add(1, std::memory_order_relaxed);
          return lost;
        };
      std::vector<Page> trial_pages;
      const bool fits = options.method == PackMethod::bitmap
                            ? bitmap_pack(patches, *t.order, wc, hc_max, options.max_pages,
                                          int(options.search_depth), hopeless, t.placed, trial_pages)
                            : skyline_pack(patches, *t.order, wc, hc_max, options.max_pages, hopeless,
                                           t.placed, trial_pages);
      if (!fits) return;
      int hc = 0;
      for (const Page& pg : trial_pages) hc = std::max(hc, *std::max_element(pg.sky.begin(), pg.sky.end()));
      t.h = page_height(hc);
      if (t.h > max_size) return;
      t.pages = uint32_t(trial_pages.size());
      t.area = uint64_t(t.w) * t.h * t.pages;
      uint64_t seen = finished_best.load(std::memory_order_relaxed);
      while (t.area < seen && !finished_best.compare_exchange_weak(seen, t.area, std::memory_order_relaxed)) {
      }
    };
    // Run one trial of each order before the next width of any: the
    // winner is as often in a later order as in the first, so a small area
    // is found sooner and more of the rest stop early (the CesiumMilkTruck's
    // default encode: 6.3-7.0 s of packing before, 4.6-5.4 s after). Only
    // the running order changes; the choice below goes by trial index.
    std::vector<size_t> running(trials.size());
    for (size_t k = 0, w = 0; w < widths.size(); ++w)
      for (size_t o = 0; o < orders.size(); ++o) running[k++] = o * widths.size() + w;
    run_in_parallel(trials.size(), worker_count(trials.size()),
                    [&](size_t i, size_t) { run_trial(trials[running[i]]); });
    uint64_t best_area = UINT64_MAX;
    uint32_t best_w = 0, best_h = 0, best_pages = 0;
    std::vector<Placed> best_placed;
    for (Trial& t : trials) {
      if (t.area == UINT64_MAX) continue;
      const bool squarer = t.area == best_area && std::max(t.w, t.h) < std::max(best_w, best_h);
      if (t.area < best_area || squarer) {
        best_area = t.area, best_w = t.w, best_h = t.h, best_pages = t.pages;
        best_placed = std::move(t.placed);
      }
    }
    if (best_area == UINT64_MAX) {
      scale = double(float(scale * options.shrink_factor));
      ++result.report.shrink_retries;
      continue;
    }
    // Placements.
    result.maps.resize(prims.size());
    for (size_t i = 0; i < prims.size(); ++i) {
      UvMap& m = result.maps[i];
      m.texel_scale = float(scale);
      m.atlas_width = best_w;
      m.atlas_height = best_h;
      m.page_count = best_pages;
      m.patch_count = prims[i].patch_count;
      m.patch_of_face.assign(prims[i].patch_of_face.begin(), prims[i].patch_of_face.end());
      m.seeds.assign(prims[i].seeds.begin(), prims[i].seeds.end());
      m.methods.assign(prims[i].methods.begin(), prims[i].methods.end());
      m.solve = prims[i].solve;
      m.placements.assign(m.patch_count, PatchPlacement{});
    }
    for (size_t pi = 0; pi < patches.size(); ++pi) {
      const PatchInfo& p = patches[pi];
      if (p.copy_of >= 0) continue;
      const Placed& pl = best_placed[pi];
      const Mask& mk = p.masks[pl.mask];
      PatchPlacement& out = result.maps[p.prim].placements[p.patch];
      out.rotation = mk.code;
      out.x = pl.cx * cell - mk.bx0;
      out.y = pl.cy * cell - mk.by0;
      out.page = uint32_t(pl.page);
      out.scale_step = p.scale_step;
      if (p.aligned) {
        // The mask holds the fraction already: whole texels here, then the
        // fraction (k/256 exactly; 1 carries into the whole part).
        const AlignedTransform& at = p.aligned_at[pl.mask];
        ++result.report.aligned_patches;
        if (at.coarse) {  // whole texels: the mask's code and the step
          out.scale_step = at.scale_step;
          continue;
        }
        out.fine = true;
        out.cos_q = at.cos_q, out.sin_q = at.sin_q;
        out.scale_step = at.scale_step;
        const auto fraction = [](double f, int32_t& whole, uint32_t& frac) {
          const long long q = std::llround(f * kFineFracSteps);
          whole += int32_t(q / kFineFracSteps), frac = uint32_t(q % kFineFracSteps);
        };
        fraction(at.frac_x, out.x, out.x_frac);
        fraction(at.frac_y, out.y, out.y_frac);
      }
    }
    PackReport& rep = result.report;
    for (const PatchInfo& p : patches) {
      if (p.copy_of < 0) continue;
      const PatchInfo& o = patches[size_t(p.copy_of)];
      const PatchPlacement& original = result.maps[o.prim].placements[o.patch];
      result.maps[p.prim].placements[p.patch] =
          copy_placement(original, p.fit, double(float(scale)), best_w, best_h);
      ++rep.reused_patches;
      const double ps = scale * pscale(p.scale_step);
      for (uint32_t f : p.faces) rep.reused_texels += layout_face_area(prims[p.prim].corner_xy, f) * ps * ps;
    }
    rep.trials = uint32_t(trials.size());
    rep.stopped_trials = stopped.load();
    rep.atlas_width = best_w;
    rep.atlas_height = best_h;
    rep.page_count = best_pages;
    rep.patch_count = uint32_t(patches.size());
    rep.texel_scale = scale;
    measure_atlas(prims, result.maps, rep);
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return PackStatus::ok;
  }
  return PackStatus::too_large;
}

}  // namespace gltfwarp
