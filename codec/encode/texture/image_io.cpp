// In-memory image decode/encode (sources in image_io.h).
#include "codec/encode/texture/image_io.h"

#include "codec/encode/texture/jpeg_writer.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <png.h>

#include <algorithm>
#include <cstring>
#include <thread>
#include <vector>

namespace gltfwarp {

using OIIO::ImageBuf;
using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

const char* to_string(ImageCodec c) {
  switch (c) {
    case ImageCodec::png:
      return "png";
    case ImageCodec::jpeg:
      return "jpeg";
    case ImageCodec::webp:
      return "webp";
    case ImageCodec::ktx2:
      return "ktx2";
    case ImageCodec::other:
      return "other";
    case ImageCodec::unknown:
      break;
  }
  return "unknown";
}

const char* mime_type(ImageCodec c) {
  switch (c) {
    case ImageCodec::png:
      return "image/png";
    case ImageCodec::jpeg:
      return "image/jpeg";
    case ImageCodec::webp:
      return "image/webp";
    case ImageCodec::ktx2:
      return "image/ktx2";
    default:
      return "";
  }
}

ImageCodec codec_of_mime(const std::string& mime) {
  for (ImageCodec c : {ImageCodec::png, ImageCodec::jpeg, ImageCodec::webp, ImageCodec::ktx2})
    if (mime == mime_type(c)) return c;
  return ImageCodec::unknown;
}

bool lossy_mime(const std::string& mime) { return mime == "image/jpeg" || mime == "image/webp"; }

ImageCodec sniff_image_codec(std::span<const uint8_t> b) {
  static const uint8_t png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  static const uint8_t ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  if (b.size() >= 8 && std::memcmp(b.data(), png, 8) == 0) return ImageCodec::png;
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return ImageCodec::jpeg;
  if (b.size() >= 12 && std::memcmp(b.data(), ktx2, 12) == 0) return ImageCodec::ktx2;
  if (b.size() >= 12 && std::memcmp(b.data(), "RIFF", 4) == 0 && std::memcmp(b.data() + 8, "WEBP", 4) == 0)
    return ImageCodec::webp;
  return b.empty() ? ImageCodec::unknown : ImageCodec::other;
}

bool png_holds_only_pixels(std::span<const uint8_t> bytes) {
  static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || !std::equal(kSignature, kSignature + 8, bytes.begin())) return false;
  // Pixels, and what no viewer shows (print size, image offset, time).
  static constexpr const char* kPixelChunks[] = {"IHDR", "PLTE", "IDAT", "IEND", "tRNS",
                                                 "sRGB", "pHYs", "oFFs", "tIME"};
  size_t at = 8;
  while (at + 12 <= bytes.size()) {
    const uint32_t length = uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 |
                            uint32_t(bytes[at + 2]) << 8 | bytes[at + 3];
    const std::string type(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
    if (std::none_of(std::begin(kPixelChunks), std::end(kPixelChunks),
                     [&](const char* t) { return type == t; }))
      return false;
    if (length > bytes.size() - at - 12) return false;
    at += 12 + size_t(length);
    if (type == "IEND") return at == bytes.size();
  }
  return false;
}

int estimate_jpeg_quality(std::span<const uint8_t> b) {
  // DQT stores the table in zigzag order; this is the standard table in zigzag order.
  static const int std_lum[64] = {16, 11, 12,  14,  12,  10, 16, 14,  13,  14,  18,  17,  16, 19,  24,  40,
                                  26, 24, 22,  22,  24,  49, 35, 37,  29,  40,  58,  51,  61, 60,  57,  51,
                                  56, 55, 64,  72,  92,  78, 64, 68,  87,  69,  55,  56,  80, 109, 81,  87,
                                  95, 98, 103, 104, 103, 62, 77, 113, 121, 112, 100, 120, 92, 101, 103, 99};
  size_t i = 2;
  while (i + 4 <= b.size()) {
    if (b[i] != 0xFF) return 0;
    const uint8_t marker = b[i + 1];
    if (marker == 0xD9 || marker == 0xDA) return 0;  // end of image / start of scan
    const size_t len = size_t(b[i + 2]) << 8 | b[i + 3];
    if (len < 2 || i + 2 + len > b.size()) return 0;
    if (marker == 0xDB) {
      size_t k = i + 4;
      while (k < i + 2 + len) {
        const int pq = b[k] >> 4, tq = b[k] & 15;
        const size_t n = pq ? 128 : 64;
        if (k + 1 + n > i + 2 + len) return 0;
        if (tq == 0) {
          double ratio = 0;
          for (int e = 0; e < 64; ++e) {
            const int q = pq ? (b[k + 1 + 2 * e] << 8 | b[k + 2 + 2 * e]) : b[k + 1 + e];
            ratio += double(q) * 100.0 / std_lum[e];
          }
          const double scale = ratio / 64.0;  // IJG: scale = q < 50 ? 5000/q : 200 - 2q
          const double q = scale <= 100 ? (200.0 - scale) / 2.0 : 5000.0 / scale;
          return std::clamp(int(q + 0.5), 1, 100);
        }
        k += 1 + n;
      }
    }
    i += 2 + len;
  }
  return 0;
}

namespace {

// The first error libpng meets reading a whole PNG, or "". OpenImageIO's PNG
// reader keeps libpng's default handlers, which print each error to stderr
// ahead of the one line we report; libpng's simplified API keeps its message
// instead. So a PNG is read once here before OpenImageIO decodes it: one
// more decode of each PNG source, for an error that stays one line.
std::string png_read_error(std::span<const uint8_t> bytes) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) return image.message;
  // One byte a texel (the values are thrown away); past the size decode_image
  // refuses anyway, OpenImageIO's refusal stands.
  if (uint64_t(image.width) * image.height > (uint64_t(1) << 28)) {
    png_image_free(&image);
    return "";
  }
  image.format = PNG_FORMAT_GRAY;
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
  const bool ok = png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0;
  const std::string message = ok ? std::string() : std::string(image.message);
  png_image_free(&image);
  return message;
}

}  // namespace

std::string decode_image(std::span<const uint8_t> bytes, DecodedImage& out) {
  out = DecodedImage{};
  out.codec = sniff_image_codec(bytes);
  if (bytes.empty()) return "empty image data";
  if (out.codec == ImageCodec::ktx2) return "KTX2 images cannot be decoded here (pass through)";
  if (out.codec == ImageCodec::png)
    if (const std::string e = png_read_error(bytes); !e.empty()) return "cannot decode png image: " + e;
  const char* name = out.codec == ImageCodec::png    ? "image.png"
                     : out.codec == ImageCodec::jpeg ? "image.jpg"
                     : out.codec == ImageCodec::webp ? "image.webp"
                                                     : "image.png";
  OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
  // glTF images hold straight (unassociated) alpha: keep it that way.
  ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
  auto in = ImageInput::open(name, &config, &reader);
  if (!in) {
    std::string e = OIIO::geterror();
    return "cannot decode " + std::string(to_string(out.codec)) + " image" +
           (e.empty() ? std::string() : ": " + e.substr(0, e.find('\n')));
  }
  const ImageSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
    return "image has no pixels";
  if (uint64_t(spec.width) * spec.height > (uint64_t(1) << 28)) return "image too large";
  ImageSpec bspec(spec.width, spec.height, spec.nchannels, spec.format);
  bspec.alpha_channel = spec.alpha_channel;
  out.pixels.reset(bspec);
  if (!in->read_image(0, 0, 0, spec.nchannels, spec.format, out.pixels.localpixels())) {
    std::string e = in->geterror();
    out.pixels.clear();
    return "cannot decode image: " + e.substr(0, e.find('\n'));
  }
  in->close();
  if (out.codec == ImageCodec::jpeg) out.jpeg_quality = estimate_jpeg_quality(bytes);
  return "";
}

namespace {

// One encode; png_filter is OIIO's "png:filter" (0: libpng's adaptive choice,
// else a mask of PNG_FILTER_* bits).
std::string encode_once(const ImageBuf& image, const ImageEncodeOptions& options, int png_filter,
                        std::vector<uint8_t>& bytes) {
  bytes.clear();
  if (!image.initialized()) return "empty image";
  const ImageSpec& src = image.spec();
  const bool jpeg = options.codec == ImageCodec::jpeg, webp = options.codec == ImageCodec::webp;
  if (!jpeg && !webp && options.codec != ImageCodec::png)
    return "only PNG, JPEG and WebP output are supported";
  int nch = src.nchannels;
  if (nch < 1 || nch > 4) return "unsupported channel count";
  if (jpeg && (nch == 2 || nch == 4)) --nch;  // JPEG has no alpha
  if (webp && nch < 3) {                      // WebP codes RGB(A): grey (and grey+alpha) go out as RGB (RGBA)
    const int order[4] = {0, 0, 0, 1};
    const ImageBuf rgb =
        OIIO::ImageBufAlgo::channels(image, nch + 2, OIIO::cspan<int>(order, size_t(nch + 2)));
    return encode_once(rgb, options, png_filter, bytes);
  }
  if (jpeg) {  // libjpeg itself, for optimised Huffman tables (jpeg_writer.h)
    std::vector<uint8_t> pixels(size_t(src.width) * size_t(src.height) * size_t(nch));
    const OIIO::ROI roi(src.x, src.x + src.width, src.y, src.y + src.height, 0, 1, 0, nch);
    if (!image.get_pixels(roi, TypeDesc::UINT8, pixels.data()))
      return "cannot read pixels: " + image.geterror();
    return encode_jpeg(pixels, src.width, src.height, nch, options.quality, bytes);
  }
  const TypeDesc fmt = (!webp && src.format.size() > 1) ? TypeDesc::UINT16 : TypeDesc::UINT8;
  ImageSpec spec(src.width, src.height, nch, fmt);
  if (nch == 2 || nch == 4) {
    spec.alpha_channel = nch - 1;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // straight alpha in, straight alpha out
  }
  const std::string quality = std::to_string(std::clamp(options.quality, 1, 100));
  if (webp) {
    spec.attribute("Compression", "webp:" + quality);  // lossy VP8 (OIIO's WebP writer)
  } else {
    spec.attribute("png:compressionLevel", std::clamp(options.png_compression, 0, 9));
    if (png_filter != 0) spec.attribute("png:filter", png_filter);
  }
  const char* name = webp ? "out.webp" : "out.png";
  OIIO::Filesystem::IOVecOutput writer(bytes);
  auto o = ImageOutput::create(name, &writer);
  if (!o) return "no " + std::string(to_string(options.codec)) + " writer: " + OIIO::geterror();
  if (!o->supports("ioproxy"))
    return "the " + std::string(to_string(options.codec)) + " writer cannot write to memory";
  if (!o->open(name, spec)) return "cannot start encoding: " + o->geterror();
  std::vector<uint8_t> row(size_t(src.width) * nch * fmt.size());
  for (int y = 0; y < src.height; ++y) {
    const OIIO::ROI roi(src.x, src.x + src.width, src.y + y, src.y + y + 1, 0, 1, 0, nch);
    if (!image.get_pixels(roi, fmt, row.data())) return "cannot read pixels: " + image.geterror();
    if (!o->write_scanline(y, 0, fmt, row.data())) return "cannot encode: " + o->geterror();
  }
  if (!o->close()) return "cannot finish encoding: " + o->geterror();
  return "";
}

}  // namespace

std::string encode_image(const ImageBuf& image, const ImageEncodeOptions& options,
                         std::vector<uint8_t>& bytes) {
  if (options.codec != ImageCodec::png || !options.png_try_unfiltered)
    return encode_once(image, options, 0, bytes);
  // The two PNG passes side by side: level-9 deflate of an atlas-sized page
  // takes seconds each (the 1M-face sample's encode).
  constexpr int kPngFilterNone = 0x08;  // PNG_FILTER_NONE
  std::vector<uint8_t> unfiltered;
  std::string unfiltered_error;
  std::thread second([&] { unfiltered_error = encode_once(image, options, kPngFilterNone, unfiltered); });
  std::string error = encode_once(image, options, 0, bytes);
  second.join();
  if (!error.empty()) return error;
  if (unfiltered_error.empty() && unfiltered.size() < bytes.size()) bytes.swap(unfiltered);
  return "";
}

bool image_size(std::span<const uint8_t> bytes, int& width, int& height, std::string& error) {
  width = height = 0;
  const ImageCodec codec = sniff_image_codec(bytes);
  if (codec == ImageCodec::ktx2) {
    // KTX2 header: pixelWidth and pixelHeight are little-endian uint32 at 20 and 24.
    if (bytes.size() < 28) return error = "truncated KTX2 header", false;
    auto u32 = [&](size_t o) {
      return uint32_t(bytes[o]) | uint32_t(bytes[o + 1]) << 8 | uint32_t(bytes[o + 2]) << 16 |
             uint32_t(bytes[o + 3]) << 24;
    };
    width = int(std::min<uint32_t>(u32(20), 1u << 30));
    height = int(std::min<uint32_t>(std::max<uint32_t>(u32(24), 1), 1u << 30));
    return true;
  }
  if (bytes.empty()) return error = "empty image data", false;
  const char* name = codec == ImageCodec::jpeg   ? "image.jpg"
                     : codec == ImageCodec::webp ? "image.webp"
                                                 : "image.png";
  OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
  ImageSpec config;
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
  auto in = ImageInput::open(name, &config, &reader);
  if (!in) {
    std::string e = OIIO::geterror();
    error = "cannot read the image header" + (e.empty() ? std::string() : ": " + e.substr(0, e.find('\n')));
    return false;
  }
  width = in->spec().width;
  height = in->spec().height;
  return true;
}

bool decode_image(std::span<const uint8_t> bytes, ImageBuf& pixels, std::string& error) {
  DecodedImage d;
  error = decode_image(bytes, d);
  if (!error.empty()) return false;
  pixels = std::move(d.pixels);
  return true;
}

bool encode_image(const ImageBuf& image, const std::string& mime, int quality, std::vector<uint8_t>& bytes,
                  std::string& error) {
  ImageEncodeOptions o;
  o.codec = lossy_mime(mime) ? codec_of_mime(mime) : ImageCodec::png;
  o.quality = quality;
  error = encode_image(image, o, bytes);
  return error.empty();
}

}  // namespace gltfwarp
