// Indexed-colour PNG through libpng's simplified API (sources in png_palette.h).
#include "codec/encode/texture/png_palette.h"

#include <png.h>

#include <algorithm>
#include <limits>
#include <unordered_map>

namespace gltfwarp {

namespace {

// Frees the png_image's internal state on every path out.
struct PngImage {
  png_image image{};
  PngImage() { image.version = PNG_IMAGE_VERSION; }
  ~PngImage() { png_image_free(&image); }
  PngImage(const PngImage&) = delete;
  PngImage& operator=(const PngImage&) = delete;
};

bool is_indexed_png(std::span<const uint8_t> b) {
  // Signature (8) + IHDR length (4) + "IHDR" (4) + width, height (8) + bit depth, colour type.
  static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  return b.size() >= 26 && std::equal(sig, sig + 8, b.begin()) && b[24] <= 8 && b[25] == 3;
}

}  // namespace

std::vector<PaletteEntry> png_palette(std::span<const uint8_t> png) {
  if (!is_indexed_png(png)) return {};
  PngImage p;
  if (!png_image_begin_read_from_memory(&p.image, png.data(), png.size())) return {};
  if (!(p.image.format & PNG_FORMAT_FLAG_COLORMAP) || p.image.colormap_entries == 0 ||
      p.image.colormap_entries > 256)
    return {};
  // The simplified reader hands out the palette only with the pixels.
  p.image.format = PNG_FORMAT_RGBA_COLORMAP;
  const size_t texels = size_t(p.image.width) * p.image.height;
  if (texels == 0 || texels > (size_t(1) << 28)) return {};
  std::vector<uint8_t> indices(texels);
  std::vector<PaletteEntry> palette(256);
  if (!png_image_finish_read(&p.image, nullptr, indices.data(), 0, palette.data())) return {};
  palette.resize(p.image.colormap_entries);
  return palette;
}

namespace {

uint32_t colour_key(const uint8_t* t, int nch) {
  const uint8_t a = nch == 4 ? t[3] : 255;
  return uint32_t(t[0]) | uint32_t(t[1]) << 8 | uint32_t(t[2]) << 16 | uint32_t(a) << 24;
}

bool palette_image(const OIIO::ImageBuf& image) {
  const OIIO::ImageSpec& spec = image.spec();
  return image.initialized() && spec.format == OIIO::TypeDesc::UINT8 && spec.nchannels >= 3 &&
         spec.nchannels <= 4 && spec.width > 0 && spec.height > 0;
}

}  // namespace

std::vector<PaletteEntry> dominant_colours(const OIIO::ImageBuf& image, double min_share,
                                           size_t max_entries) {
  if (!palette_image(image) || max_entries == 0) return {};
  const OIIO::ImageSpec& spec = image.spec();
  const int nch = spec.nchannels;
  constexpr size_t kMaxDistinct = 65536;  // beyond this, not flat art (and the count stays cheap)
  std::unordered_map<uint32_t, uint64_t> count;
  std::vector<uint8_t> row(size_t(spec.width) * nch);
  for (int y = 0; y < spec.height; ++y) {
    const OIIO::ROI roi(spec.x, spec.x + spec.width, spec.y + y, spec.y + y + 1, 0, 1, 0, nch);
    image.get_pixels(roi, OIIO::TypeDesc::UINT8, row.data());
    for (int x = 0; x < spec.width; ++x) {
      ++count[colour_key(&row[size_t(x) * nch], nch)];
      if (count.size() > kMaxDistinct) return {};
    }
  }
  std::vector<std::pair<uint64_t, uint32_t>> by_count;  // (count, colour), most frequent first
  by_count.reserve(count.size());
  for (const auto& [colour, n] : count) by_count.push_back({n, colour});
  const size_t keep = std::min(max_entries, by_count.size());
  // Ties broken by colour value, so the palette does not depend on hash order.
  std::partial_sort(by_count.begin(), by_count.begin() + std::ptrdiff_t(keep), by_count.end(),
                    [](const auto& l, const auto& r) {
                      return l.first != r.first ? l.first > r.first : l.second < r.second;
                    });
  uint64_t covered = 0;
  std::vector<PaletteEntry> palette(keep);
  for (size_t i = 0; i < keep; ++i) {
    covered += by_count[i].first;
    const uint32_t c = by_count[i].second;
    palette[i] = {uint8_t(c), uint8_t(c >> 8), uint8_t(c >> 16), uint8_t(c >> 24)};
  }
  const double texels = double(spec.width) * double(spec.height);
  if (!(double(covered) >= min_share * texels)) return {};
  return palette;
}

void snap_to_palette(OIIO::ImageBuf& image, std::span<const PaletteEntry> palette) {
  if (!palette_image(image) || palette.empty()) return;
  const std::vector<uint8_t> indices = palette_indices(image, palette);
  const OIIO::ImageSpec& spec = image.spec();
  const int nch = spec.nchannels;
  std::vector<uint8_t> row(size_t(spec.width) * nch);
  for (int y = 0; y < spec.height; ++y) {
    for (int x = 0; x < spec.width; ++x) {
      const PaletteEntry& e = palette[indices[size_t(y) * spec.width + x]];
      std::copy_n(e.begin(), nch, &row[size_t(x) * nch]);
    }
    const OIIO::ROI roi(spec.x, spec.x + spec.width, spec.y + y, spec.y + y + 1, 0, 1, 0, nch);
    image.set_pixels(roi, OIIO::TypeDesc::UINT8, row.data());
  }
}

std::vector<uint8_t> palette_indices(const OIIO::ImageBuf& image, std::span<const PaletteEntry> palette) {
  const OIIO::ImageSpec& spec = image.spec();
  const int nch = spec.nchannels;
  std::vector<uint8_t> out(size_t(spec.width) * spec.height);
  if (palette.empty() || nch < 3 || nch > 4) return out;
  std::vector<uint8_t> row(size_t(spec.width) * nch);
  // Warped atlases repeat few colours many times: remember each answer.
  std::unordered_map<uint32_t, uint8_t> nearest;
  for (int y = 0; y < spec.height; ++y) {
    const OIIO::ROI roi(spec.x, spec.x + spec.width, spec.y + y, spec.y + y + 1, 0, 1, 0, nch);
    image.get_pixels(roi, OIIO::TypeDesc::UINT8, row.data());
    for (int x = 0; x < spec.width; ++x) {
      const uint8_t* t = &row[size_t(x) * nch];
      const uint8_t a = nch == 4 ? t[3] : 255;
      const uint32_t key = colour_key(t, nch);
      auto it = nearest.find(key);
      if (it == nearest.end()) {
        int best = 0, best_d = std::numeric_limits<int>::max();
        for (size_t i = 0; i < palette.size(); ++i) {
          const PaletteEntry& e = palette[i];
          const int dr = int(e[0]) - t[0], dg = int(e[1]) - t[1], db = int(e[2]) - t[2], da = int(e[3]) - a;
          const int d = dr * dr + dg * dg + db * db + da * da;
          if (d < best_d) best_d = d, best = int(i);
        }
        it = nearest.emplace(key, uint8_t(best)).first;
      }
      out[size_t(y) * spec.width + x] = it->second;
    }
  }
  return out;
}

namespace {

// libpng's write state, its error text and the bytes it writes.
struct PngWriter {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::vector<uint8_t>* out = nullptr;
  std::string error;
  ~PngWriter() { png_destroy_write_struct(&png, &info); }
  static void on_error(png_structp png, png_const_charp message) {
    static_cast<PngWriter*>(png_get_error_ptr(png))->error = message;
    png_longjmp(png, 1);
  }
  static void on_warning(png_structp, png_const_charp) {}
  static void on_write(png_structp png, png_bytep data, size_t n) {
    std::vector<uint8_t>& out = *static_cast<PngWriter*>(png_get_io_ptr(png))->out;
    out.insert(out.end(), data, data + n);
  }
};

// Everything the write needs, prepared before setjmp so that nothing the
// longjmp could skip over is built after it.
struct IndexedPng {
  png_uint_32 width = 0, height = 0;
  std::vector<png_color> plte;
  std::vector<png_byte> trns;
  int trns_count = 0;  // 0: every entry opaque, no tRNS chunk
  std::vector<png_bytep> rows;
};

bool write_indexed(PngWriter& w, IndexedPng& plan) {
  if (setjmp(png_jmpbuf(w.png))) return false;
  png_set_write_fn(w.png, &w, &PngWriter::on_write, nullptr);
  png_set_IHDR(w.png, w.info, plan.width, plan.height, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_PLTE(w.png, w.info, plan.plte.data(), int(plan.plte.size()));
  if (plan.trns_count > 0) png_set_tRNS(w.png, w.info, plan.trns.data(), plan.trns_count, nullptr);
  png_set_compression_level(w.png, 9);
  png_set_filter(w.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_write_info(w.png, w.info);
  png_write_image(w.png, plan.rows.data());
  png_write_end(w.png, nullptr);
  return true;
}

}  // namespace

std::string encode_indexed_png(const OIIO::ImageBuf& image, std::span<const PaletteEntry> palette,
                               std::vector<uint8_t>& bytes) {
  bytes.clear();
  const OIIO::ImageSpec& spec = image.spec();
  if (!image.initialized() || spec.width <= 0 || spec.height <= 0) return "empty image";
  if (spec.nchannels < 3 || spec.nchannels > 4) return "an indexed PNG needs an RGB or RGBA image";
  if (palette.empty() || palette.size() > 256) return "a PNG palette holds 1 to 256 entries";
  const std::vector<uint8_t> indices = palette_indices(image, palette);
  // Written with libpng's full API for the settings its simplified API
  // lacks: zlib level 9 and unfiltered rows (the choice libpng's own advice
  // makes for palette images). Duck's atlas: 16.1 -> 15.3 KB of IDAT.
  IndexedPng plan;
  plan.width = png_uint_32(spec.width);
  plan.height = png_uint_32(spec.height);
  plan.plte.resize(palette.size());
  plan.trns.resize(palette.size());
  for (size_t i = 0; i < palette.size(); ++i) {
    plan.plte[i] = {palette[i][0], palette[i][1], palette[i][2]};
    plan.trns[i] = palette[i][3];
    if (palette[i][3] != 255) plan.trns_count = int(i) + 1;  // tRNS up to the last translucent entry
  }
  plan.rows.resize(size_t(spec.height));
  for (int y = 0; y < spec.height; ++y)
    plan.rows[size_t(y)] = const_cast<png_bytep>(&indices[size_t(y) * spec.width]);
  PngWriter w;
  w.out = &bytes;
  w.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &w, &PngWriter::on_error, &PngWriter::on_warning);
  if (w.png) w.info = png_create_info_struct(w.png);
  if (!w.png || !w.info) return "cannot encode indexed PNG: out of memory";
  if (!write_indexed(w, plan)) return "cannot encode indexed PNG: " + w.error;
  return "";
}

}  // namespace gltfwarp
