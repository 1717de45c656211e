// libjpeg-turbo JPEG writer (see jpeg_writer.h). libjpeg reports errors by
// calling error_exit, which must not return: it longjmps back here. The
// function that calls setjmp holds no C++ object with a destructor, so
// nothing is skipped on that path; the output buffer is libjpeg's own
// (jpeg_mem_dest), freed on both paths.
#include "codec/encode/texture/jpeg_writer.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>

#include <jpeglib.h>

namespace gltfwarp {
namespace {

struct ErrorManager {
  jpeg_error_mgr pub;  // first: libjpeg sees a jpeg_error_mgr*
  jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void exit_on_error(j_common_ptr info) {
  auto* err = reinterpret_cast<ErrorManager*>(info->err);
  (*info->err->format_message)(info, err->message);
  std::longjmp(err->jump, 1);
}

void no_output(j_common_ptr) {}  // warnings: not to stderr

// The libjpeg calls, between setjmp and its longjmp; false with `message`
// set on an error. out/out_size: libjpeg's buffer (the caller frees it).
bool compress(const uint8_t* pixels, int width, int height, int channels, int quality, unsigned char** out,
              unsigned long* out_size, char* message) {
  jpeg_compress_struct info;
  ErrorManager err;
  info.err = jpeg_std_error(&err.pub);
  err.pub.error_exit = exit_on_error;
  err.pub.output_message = no_output;
  if (setjmp(err.jump)) {
    std::snprintf(message, JMSG_LENGTH_MAX, "%s", err.message);
    jpeg_destroy_compress(&info);
    return false;
  }
  jpeg_create_compress(&info);
  jpeg_mem_dest(&info, out, out_size);
  info.image_width = JDIMENSION(width);
  info.image_height = JDIMENSION(height);
  info.input_components = channels;
  info.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  info.optimize_coding = TRUE;
  jpeg_start_compress(&info, TRUE);
  const size_t stride = size_t(width) * size_t(channels);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(pixels + size_t(info.next_scanline) * stride);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  return true;
}

}  // namespace

std::string encode_jpeg(std::span<const uint8_t> pixels, int width, int height, int channels, int quality,
                        std::vector<uint8_t>& bytes) {
  bytes.clear();
  if (channels != 1 && channels != 3) return "JPEG takes 1 or 3 channels";
  if (width <= 0 || height <= 0 || width > JPEG_MAX_DIMENSION || height > JPEG_MAX_DIMENSION)
    return "image size out of JPEG's range";
  if (pixels.size() != size_t(width) * size_t(height) * size_t(channels)) return "pixel count mismatch";
  unsigned char* out = nullptr;
  unsigned long out_size = 0;
  char message[JMSG_LENGTH_MAX] = {};
  const bool ok =
      compress(pixels.data(), width, height, channels, std::clamp(quality, 1, 100), &out, &out_size, message);
  if (ok && out) bytes.assign(out, out + out_size);
  std::free(out);
  if (!ok) return std::string("cannot encode JPEG: ") + message;
  return "";
}

}  // namespace gltfwarp
