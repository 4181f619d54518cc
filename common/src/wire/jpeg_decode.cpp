#include "semfuse/wire/jpeg_decode.hpp"

#include <csetjmp>
#include <cstdio>  // jpeglib.h uses FILE and size_t without including their headers
#include <string>

#include <jpeglib.h>
// After jpeglib.h, which it needs.
#include <jerror.h>

namespace semfuse::wire {
namespace {

// libjpeg reports a fatal error by calling error_exit, which must not return: it jumps back into
// decodeJpeg. Warnings go through emit_message, which would print them to stderr; the ones that
// mean pixels were made up jump back too (damagedData), the others are counted.
struct ErrorManager {
  jpeg_error_mgr base;  // first: libjpeg sees a jpeg_error_mgr*
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  int warnings;
};

[[noreturn]] void jumpOnError(j_common_ptr info) {
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  (*info->err->format_message)(info, errors->message);
  std::longjmp(errors->jump, 1);
}

// Warnings after which libjpeg goes on with invented data: a payload that ends early (the rest of
// the image comes out grey) or whose entropy-coded data is damaged. Integrating such colour would
// paint the map with it, so the frame is refused instead. Not here: extraneous bytes before a
// marker (some webcams write them), an unknown JFIF revision, a bad ICC profile, and an
// inconsistent progression (a scan that sends coefficients again, which the scan limit bounds).
bool damagedData(int code) {
  switch (code) {
    case JWRN_JPEG_EOF:
    case JWRN_HIT_MARKER:
    case JWRN_HUFF_BAD_CODE:
    case JWRN_MUST_RESYNC:
    case JWRN_NOT_SEQUENTIAL:
#if JPEG_LIB_VERSION >= 70 || defined(C_ARITH_CODING_SUPPORTED) || defined(D_ARITH_CODING_SUPPORTED)
    case JWRN_ARITH_BAD_CODE:
#endif
      return true;
    default:
      return false;
  }
}

void onMessage(j_common_ptr info, int level) {
  if (level >= 0) return;  // trace output
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  if (!damagedData(info->err->msg_code)) {
    ++errors->warnings;
    return;
  }
  char detail[JMSG_LENGTH_MAX];
  (*info->err->format_message)(info, detail);
  std::snprintf(errors->message, sizeof(errors->message), "damaged data (%.150s)", detail);
  std::longjmp(errors->jump, 1);
}

void limitScans(j_common_ptr info) {
  const auto* decompress = reinterpret_cast<j_decompress_ptr>(info);
  if (decompress->input_scan_number <= kMaxJpegScans) return;
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  std::snprintf(errors->message, sizeof(errors->message), "more than %d scans", kMaxJpegScans);
  std::longjmp(errors->jump, 1);
}

// Both public decoders: RGB, or (keep_grey) a greyscale JPEG as one channel.
Result<cv::Mat> decodeJpeg(const uint8_t* data, std::size_t size, cv::Size expected, bool keep_grey, int* warnings) {
  if (data == nullptr || size == 0) return makeError("empty JPEG payload");
  if (expected.width <= 0 || expected.height <= 0) return makeError("no image size to decode a JPEG into");
  // Everything that must outlive a jump back here exists before setjmp and is not changed after
  // it (C++ objects and setjmp mix only that way); libjpeg writes the rows into `rgb`'s buffer.
  cv::Mat rgb(expected, CV_8UC3);
  jpeg_decompress_struct info{};
  ErrorManager errors{};
  jpeg_progress_mgr progress{};
  progress.progress_monitor = limitScans;
  info.err = jpeg_std_error(&errors.base);
  errors.base.error_exit = jumpOnError;
  errors.base.emit_message = onMessage;
  jpeg_create_decompress(&info);
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&info);
    return makeError(std::string("JPEG payload does not decode: ") + errors.message);
  }
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);
  info.progress = &progress;
  const bool grey = keep_grey && info.jpeg_color_space == JCS_GRAYSCALE;  // read only if no jump comes
  info.out_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
  if (static_cast<int>(info.image_width) != expected.width || static_cast<int>(info.image_height) != expected.height) {
    const std::string declared = std::to_string(info.image_width) + "x" + std::to_string(info.image_height);
    jpeg_destroy_decompress(&info);
    return makeError("JPEG payload declares " + declared + ", expected " + std::to_string(expected.width) + "x" +
                     std::to_string(expected.height));
  }
  jpeg_start_decompress(&info);
  // Grey rows are packed at the start of the RGB buffer (allocated before setjmp, at the most a
  // decode can need).
  const std::size_t row_bytes = static_cast<std::size_t>(expected.width) * (grey ? 1 : 3);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = rgb.data + row_bytes * info.output_scanline;
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
  if (warnings) *warnings = errors.warnings;
  if (grey) return cv::Mat(expected, CV_8UC1, rgb.data).clone();
  return rgb;
}

}  // namespace

Result<cv::Mat> decodeJpegRgb(const uint8_t* data, std::size_t size, cv::Size expected, int* warnings) {
  return decodeJpeg(data, size, expected, false, warnings);
}

Result<cv::Mat> decodeJpegRgbOrGrey(const uint8_t* data, std::size_t size, cv::Size expected, int* warnings) {
  return decodeJpeg(data, size, expected, true, warnings);
}

}  // namespace semfuse::wire
