// The sRGB transfer functions (IEC 61966-2-1), in the form every pixel path
// of the encoder shares: the warp's staging, the texture sampler's load, and
// the quality measures all convert through these, so that their linear
// values agree bit for bit.
#pragma once

namespace gltfwarp {

float srgb_to_linear(float v);
float linear_to_srgb(float v);

// srgb_to_linear(v) with the same bits, by a 256-entry table when v is one of
// the floats OpenImageIO's get_pixels makes of an 8-bit channel (k/255 as it
// rounds it), else by the formula. A 4096² texture loads 50 M channels.
float srgb_to_linear_of_pixel(float v);

}  // namespace gltfwarp
