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
#include <cstring>

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

// Whether the saved marker `m` is one that libjpeg writes itself for `dst`
// (its JFIF APP0 or Adobe APP14): copying it too would duplicate it.
bool written_by_libjpeg(const jpeg_compress_struct& dst, jpeg_saved_marker_ptr m) {
  auto starts = [&](const char* tag, unsigned n) {
    return m->data_length >= n && std::memcmp(m->data, tag, n) == 0;
  };
  if (dst.write_JFIF_header && m->marker == JPEG_APP0 && starts("JFIF", 5)) return true;
  return dst.write_Adobe_marker && m->marker == JPEG_APP0 + 14 && starts("Adobe", 5);
}

// The coefficient copy of recode_jpeg_losslessly, as `compress` above: no
// C++ object lives between setjmp and a longjmp. Both structs start zeroed,
// so destroying one that was never created is a no-op.
bool transcode(const uint8_t* in, size_t in_size, unsigned char** out, unsigned long* out_size,
               char* message) {
  jpeg_decompress_struct src{};
  jpeg_compress_struct dst{};
  ErrorManager err;
  src.err = dst.err = jpeg_std_error(&err.pub);
  err.pub.error_exit = exit_on_error;
  err.pub.output_message = no_output;
  if (setjmp(err.jump)) {
    std::snprintf(message, JMSG_LENGTH_MAX, "%s", err.message);
    jpeg_destroy_compress(&dst);
    jpeg_destroy_decompress(&src);
    return false;
  }
  jpeg_create_decompress(&src);
  jpeg_create_compress(&dst);
  jpeg_mem_src(&src, in, static_cast<unsigned long>(in_size));
  jpeg_save_markers(&src, JPEG_COM, 0xFFFF);
  for (int m = 0; m < 16; ++m) jpeg_save_markers(&src, JPEG_APP0 + m, 0xFFFF);
  jpeg_read_header(&src, TRUE);
  jvirt_barray_ptr* coefficients = jpeg_read_coefficients(&src);
  // libjpeg reads on past damage (a premature end, corrupt entropy data)
  // with a warning, filling in what is missing: such a file stays as it is.
  if (src.err->num_warnings > 0) {
    std::snprintf(message, JMSG_LENGTH_MAX, "damaged data (%ld libjpeg warnings)", src.err->num_warnings);
    jpeg_destroy_compress(&dst);
    jpeg_destroy_decompress(&src);
    return false;
  }
  jpeg_copy_critical_parameters(&src, &dst);
  dst.optimize_coding = TRUE;
  jpeg_mem_dest(&dst, out, out_size);
  jpeg_write_coefficients(&dst, coefficients);
  for (jpeg_saved_marker_ptr m = src.marker_list; m; m = m->next)
    if (!written_by_libjpeg(dst, m)) jpeg_write_marker(&dst, m->marker, m->data, m->data_length);
  jpeg_finish_compress(&dst);
  jpeg_finish_decompress(&src);
  jpeg_destroy_compress(&dst);
  jpeg_destroy_decompress(&src);
  return true;
}

// libjpeg's output buffer, freed on every path, into `bytes` when `ok`.
std::string take_output(bool ok, unsigned char* out, unsigned long out_size, const char* what,
                        const char* message, std::vector<uint8_t>& bytes) {
  if (ok && out) bytes.assign(out, out + out_size);
  std::free(out);
  if (!ok) return std::string(what) + message;
  return "";
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
  return take_output(ok, out, out_size, "cannot encode JPEG: ", message, bytes);
}

std::string recode_jpeg_losslessly(std::span<const uint8_t> jpeg, std::vector<uint8_t>& bytes) {
  bytes.clear();
  if (jpeg.size() < 4) return "not a JPEG";
  unsigned char* out = nullptr;
  unsigned long out_size = 0;
  char message[JMSG_LENGTH_MAX] = {};
  const bool ok = transcode(jpeg.data(), jpeg.size(), &out, &out_size, message);
  return take_output(ok, out, out_size, "cannot re-code JPEG: ", message, bytes);
}

}  // namespace gltfwarp
