#include "image_files.hpp"

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace semfuse::datasets::detail {
namespace {

// cv::imread returns an empty Mat for both "missing" and "corrupt"; tell the two apart.
Error unreadable(const std::filesystem::path& file, const char* what) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return makeError(std::string(what) + " missing: " + file.string());
  return makeError(std::string(what) + " cannot be decoded (corrupt or not an image): " + file.string());
}

}  // namespace

Result<cv::Mat> readDepthAsMetres(const std::filesystem::path& file, double metres_per_unit,
                                  bool saturated_is_invalid) {
  const cv::Mat raw = cv::imread(file.string(), cv::IMREAD_ANYDEPTH);
  if (raw.empty()) return unreadable(file, "depth image");
  if (raw.type() != CV_16UC1) {
    return makeError("depth image is not 16-bit single channel (OpenCV type " + std::to_string(raw.type()) +
                     "): " + file.string());
  }
  cv::Mat metres;
  raw.convertTo(metres, CV_32F, metres_per_unit);
  if (saturated_is_invalid) metres.setTo(0.0f, raw == 65535);
  return metres;
}

Result<cv::Mat> readColorAsRgb(const std::filesystem::path& file) {
  const cv::Mat bgr = cv::imread(file.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) return unreadable(file, "colour image");
  // Channel swap with core's mixChannels: this library links imgcodecs only, not imgproc.
  cv::Mat rgb(bgr.size(), CV_8UC3);
  const int from_to[] = {0, 2, 1, 1, 2, 0};
  cv::mixChannels(&bgr, 1, &rgb, 1, from_to, 3);
  return rgb;
}

Result<cv::Size> readImageSize(const std::filesystem::path& file) {
  const cv::Mat image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (image.empty()) return unreadable(file, "image");
  return image.size();
}

Stamp stampFromSeconds(double seconds) {
  Stamp stamp;
  const double whole = std::floor(seconds);
  stamp.sec = static_cast<int32_t>(whole);
  auto nanos = static_cast<long long>(std::llround((seconds - whole) * 1e9));
  if (nanos >= 1000000000LL) {  // rounding up to the next second
    ++stamp.sec;
    nanos -= 1000000000LL;
  }
  stamp.nanosec = static_cast<uint32_t>(nanos);
  return stamp;
}

}  // namespace semfuse::datasets::detail
