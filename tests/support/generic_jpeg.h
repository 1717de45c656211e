// JPEG bytes as most tools write them: OpenImageIO 2.4's writer, libjpeg
// with its generic Huffman tables (the encoder's own writer optimises them;
// jpeg_writer.h). Sources for tests of what the encoder does with a JPEG it
// is given.
#pragma once

#include <cstdint>
#include <vector>

#include <OpenImageIO/imagebuf.h>

namespace gltfwarp::test {

// `img`: 8-bit, 1 or 3 channels. progressive: a progressive scan instead
// of one baseline scan.
std::vector<uint8_t> generic_jpeg(const OIIO::ImageBuf& img, int quality, bool progressive = false);

}  // namespace gltfwarp::test
