// Indexed-colour PNG: read a source's palette, write an atlas with it.
//
// A palette PNG stores one byte per texel and compresses far better than the
// truecolour image a warp produces, whose filtered texels take thousands of
// new colours. "PNG stays PNG" therefore means "an indexed PNG stays
// indexed, with its own palette": every warped texel is snapped to the
// nearest palette entry, so the atlas holds only colours the source held.
//
// Source: libpng 1.6's simplified API (png.h, "SIMPLIFIED API"):
// png_image_begin_read_from_memory / png_image_finish_read with a colormap
// format, and png_image_write_to_memory (libpng >= 1.6.29).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

namespace gltfwarp {

using PaletteEntry = std::array<uint8_t, 4>;  // straight RGBA, sRGB as stored

// The palette of an indexed (colour type 3, 1 to 8 bits) PNG, with tRNS alpha folded
// in; empty for any other image (truecolour, grey, JPEG, corrupt bytes).
std::vector<PaletteEntry> png_palette(std::span<const uint8_t> png);

// Encodes `image` (uint8, 3 or 4 channels) as an indexed PNG whose palette is
// `palette` (1..256 entries): each texel becomes the entry nearest to it
// (squared distance over RGBA). Returns "" on success or a one-line error.
std::string encode_indexed_png(const OIIO::ImageBuf& image, std::span<const PaletteEntry> palette,
                               std::vector<uint8_t>& bytes);

// The palette of flat-coloured art that is not stored indexed: the
// `max_entries` most frequent colours of `image` (uint8, 3 or 4 channels),
// most frequent first, when together they cover at least `min_share` of its
// texels; empty otherwise (photographs, gradients, more than 65,536
// distinct colours, other formats). Fox's truecolour texture: 5 colours
// cover 99.5% of it, 256 cover 99.7%; every other corpus texture fails.
std::vector<PaletteEntry> dominant_colours(const OIIO::ImageBuf& image, double min_share = 0.99,
                                           size_t max_entries = 256);

// Replaces every texel of `image` (uint8, 3 or 4 channels) by its nearest
// palette entry: the image an indexed PNG written with `palette` decodes to,
// so a quality check made after it measures what the viewer will show.
void snap_to_palette(OIIO::ImageBuf& image, std::span<const PaletteEntry> palette);

// The nearest-entry index of every texel, row-major (exposed for tests).
std::vector<uint8_t> palette_indices(const OIIO::ImageBuf& image, std::span<const PaletteEntry> palette);

}  // namespace gltfwarp
