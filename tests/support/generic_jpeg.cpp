#include "support/generic_jpeg.h"

#include <string>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

namespace gltfwarp::test {

std::vector<uint8_t> generic_jpeg(const OIIO::ImageBuf& img, int quality, bool progressive) {
  std::vector<uint8_t> bytes;
  OIIO::ImageSpec spec(img.spec().width, img.spec().height, img.spec().nchannels, OIIO::TypeDesc::UINT8);
  spec.attribute("Compression", "jpeg:" + std::to_string(quality));
  if (progressive) spec.attribute("jpeg:progressive", 1);
  OIIO::Filesystem::IOVecOutput writer(bytes);
  auto out = OIIO::ImageOutput::create("out.jpg", &writer);
  if (!out || !out->open("out.jpg", spec) || !out->write_image(OIIO::TypeDesc::UINT8, img.localpixels()) ||
      !out->close())
    bytes.clear();
  return bytes;
}

}  // namespace gltfwarp::test
