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

}  // namespace gltfwarp
