// Image bytes <-> pixels, in memory, through OpenImageIO (no temporary files);
// JPEG output through libjpeg itself (jpeg_writer.h).
//
// Source: OIIO 2.4's IOProxy interface (Filesystem::IOMemReader and
// IOVecOutput), as documented in the OpenImageIO manual, "Custom I/O proxies".
// JPEG quality estimation inverts the IJG quality scaling of the standard
// luminance quantization table (ITU-T T.81 Annex K, libjpeg jcparam.c).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

namespace gltfwarp {

enum class ImageCodec : uint8_t { unknown, png, jpeg, webp, ktx2, other };
const char* to_string(ImageCodec c);

// By magic bytes; never decodes.
ImageCodec sniff_image_codec(std::span<const uint8_t> bytes);

// glTF mimeType for a codec ("image/png", "image/jpeg", ...; "" for unknown).
const char* mime_type(ImageCodec c);
// The codec a mimeType names (unknown for others).
ImageCodec codec_of_mime(const std::string& mime);
// JPEG and WebP (as we write it): what a viewer shows is not the pixels coded.
bool lossy_mime(const std::string& mime);

struct DecodedImage {
  OIIO::ImageBuf pixels;  // first subimage, native format (uint8 or uint16 usually)
  ImageCodec codec = ImageCodec::unknown;
  int jpeg_quality = 0;  // estimated IJG quality (1..100) for JPEG sources, else 0
};

// Decodes PNG, JPEG or anything else OIIO reads from memory. Returns "" on
// success, or a one-line error (e.g. for KTX2/Basis, which OIIO cannot
// decode: the caller should then pass the image through untouched).
std::string decode_image(std::span<const uint8_t> bytes, DecodedImage& out);

struct ImageEncodeOptions {
  ImageCodec codec = ImageCodec::png;  // png, jpeg or webp (lossy)
  int quality = 90;                    // lossy coders, 1..100: JPEG's IJG scale, libwebp's quality
  int png_compression = 9;             // zlib level 0..9
  // PNG: also encode with every row unfiltered and keep the smaller file.
  // libpng's adaptive filter choice suits photographs; flat-coloured art
  // (and warped atlases of it, like the Fox's) often codes far smaller
  // unfiltered, while photographic textures (TwoSidedPlane's base colour) go
  // the other way (image bytes: benchmarks/results/results.md).
  bool png_try_unfiltered = true;
};

// Encodes `image` (1..4 channels; JPEG drops alpha, WebP keeps it) into
// `bytes`. Returns "" on success or a one-line error.
std::string encode_image(const OIIO::ImageBuf& image, const ImageEncodeOptions& options,
                         std::vector<uint8_t>& bytes);

// Convenience forms returning true on success, the error in `error`.
// Width and height from the header only (no pixel decode).
bool image_size(std::span<const uint8_t> bytes, int& width, int& height, std::string& error);
bool decode_image(std::span<const uint8_t> bytes, OIIO::ImageBuf& pixels, std::string& error);
// mime "image/jpeg" or "image/webp" gives that lossy coder at `quality`,
// anything else PNG.
bool encode_image(const OIIO::ImageBuf& image, const std::string& mime, int quality,
                  std::vector<uint8_t>& bytes, std::string& error);

// True for a well-formed PNG whose chunks all describe pixels alone (IHDR,
// PLTE, IDAT, IEND, tRNS, sRGB, and pHYs, oFFs, tIME, which no viewer
// shows): re-encoding its decoded pixels then
// loses nothing. A colour profile (iCCP, gAMA, cHRM, sBIT), text or any
// other chunk would be lost, so such a PNG is not one.
bool png_holds_only_pixels(std::span<const uint8_t> bytes);

// Estimated IJG quality of JPEG bytes from their luminance quantization
// table, or 0 when there is none.
int estimate_jpeg_quality(std::span<const uint8_t> bytes);

}  // namespace gltfwarp
