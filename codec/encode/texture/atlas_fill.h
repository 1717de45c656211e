// What the atlas holds where no patch and no gutter reaches: a pull-push
// fill (the pyramid fill of Gortler et al., "The Lumigraph", SIGGRAPH 1996,
// section 3.5.2, as texture bakers pad their atlases). Each empty texel takes
// the colour the nearby patches have, blurred more the farther they are, so
//  * the MIP levels a viewer builds blend patch borders with colours like
//    their own, not with a foreign flat colour, once the gutter runs out;
//  * JPEG meets no sharp step between content and fill at patch outlines.
#pragma once

#include <cstdint>
#include <span>

namespace gltfwarp {

// pixels: width * height texels of `channels` interleaved 8-bit (deep =
// false) or 16-bit (deep = true) values, row-major. empty: one flag per
// texel, non-zero where the texel is to be filled. Texels not flagged are
// left untouched; when no texel is kept, every texel becomes 0.
void pull_push_fill(uint8_t* pixels, int width, int height, int channels, bool deep,
                    std::span<const uint8_t> empty);

// The other fill, for PNG: each empty texel copies its nearest kept texel
// (Euclidean distance between texel centres; the exact distance transform
// with its nearest points, Felzenszwalb & Huttenlocher, "Distance Transforms
// of Sampled Functions", Theory of Computing 8, 2012). The gutter's own
// dilation, carried to the whole page. A viewer's MIP levels then average
// a patch's border with its own colours at every level, where a flat mean
// fill tints it (the Fox's white chest took orange seam lines at 256 px).
// Flat art comes out as large flat regions, cheap for PNG's filters: the
// Fox's atlas is smaller than with the mean. Same arguments as
// pull_push_fill; when no texel is kept, every texel becomes 0.
void nearest_fill(uint8_t* pixels, int width, int height, int channels, bool deep,
                  std::span<const uint8_t> empty);

// For block coders (JPEG, WebP), after pull_push_fill: every aligned
// block x block square (clipped at the right and bottom edges) in which
// every texel is empty becomes flat, each channel the square's rounded mean.
// A flat block is a DC coefficient and an end-of-block code, where a smooth
// gradient still spends AC coefficients. Run with 16 (JPEG's 4:2:0
// macroblock, so the chroma block is flat too) and then 8 (its DCT block).
// The viewer never samples such a block at full resolution, and its mean,
// what MIP level 3 (8x8) averages, is the fill's: at JPEG q50 the
// CesiumMilkTruck's atlas came out 7% smaller and the Fox's 12%, at the same
// surface PSNR at MIP levels 0-3. Same arguments as pull_push_fill; bad
// sizes or block < 1 leave the pixels untouched.
void flatten_empty_blocks(uint8_t* pixels, int width, int height, int channels, bool deep,
                          std::span<const uint8_t> empty, int block);

}  // namespace gltfwarp
