// JPEG output through libjpeg-turbo itself (Debian's libjpeg62-turbo), for
// the one setting OpenImageIO 2.4's JPEG writer does not expose: Huffman
// tables optimised for the image (libjpeg's optimize_coding, what sharp
// and so gltf-transform write by default). The same quantisation, 4:2:0
// chroma and baseline (sequential) scan as before; only the entropy code
// is shorter: the corpus's images at quality 50 came out 7-60% smaller
// (CesiumMilkTruck 162,786 -> 125,074 B), pixel for pixel the same.
// Progressive scans were smaller on some images and larger on others, and
// cost viewers a slower decode, so they are not used.
//
// The same optimised tables also shrink a source JPEG without touching its
// pixels (jpegtran -optimize): its DCT coefficients are copied as they are
// and only re-entropy-coded. Most JPEGs carry libjpeg's generic tables.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gltfwarp {

// pixels: width * height * channels 8-bit values, row-major, channels 1
// (greyscale) or 3 (RGB). quality: the IJG scale, clamped to 1..100.
// Returns "" and the file's bytes, or a one-line error (bytes then empty).
std::string encode_jpeg(std::span<const uint8_t> pixels, int width, int height, int channels, int quality,
                        std::vector<uint8_t>& bytes);

// `jpeg` re-coded losslessly: the same quantised coefficients (so the same
// pixels in any decoder), quantisation tables, sampling and colour space,
// with Huffman tables optimised for them in one baseline scan. Every APPn
// and COM segment (EXIF, ICC profile, XMP, comments) is carried over in
// order; only the JFIF/Adobe headers libjpeg writes itself are not
// duplicated. Restart markers are dropped (they carry no pixels).
// Returns "" and the new bytes (they may be larger: the caller compares),
// or a one-line error.
std::string recode_jpeg_losslessly(std::span<const uint8_t> jpeg, std::vector<uint8_t>& bytes);

}  // namespace gltfwarp
