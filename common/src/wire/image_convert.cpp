#include "semfuse/wire/image_convert.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace semfuse::wire {

cv::Mat depthUnitsToMetres(const cv::Mat& units, double metres_per_unit) {
  CV_Assert(units.type() == CV_16UC1);
  cv::Mat metres;
  units.convertTo(metres, CV_32F, metres_per_unit);
  return metres;
}

cv::Mat depthMetresToUnits(const cv::Mat& metres, double metres_per_unit) {
  CV_Assert(metres.type() == CV_32FC1 && metres_per_unit > 0.0);
  cv::Mat units(metres.size(), CV_16UC1);
  for (int y = 0; y < metres.rows; ++y) {
    const float* in = metres.ptr<float>(y);
    uint16_t* out = units.ptr<uint16_t>(y);
    for (int x = 0; x < metres.cols; ++x) {
      const double value = std::round(static_cast<double>(in[x]) / metres_per_unit);
      out[x] = (value > 0.0 && value <= 65535.0) ? static_cast<uint16_t>(value) : 0;  // NaN fails both
    }
  }
  return units;
}

cv::Mat swapRedBlue(const cv::Mat& image) {
  CV_Assert(image.type() == CV_8UC3);
  cv::Mat swapped;
  cv::cvtColor(image, swapped, cv::COLOR_RGB2BGR);
  return swapped;
}

cv::Mat colorizeLabels(const cv::Mat& labels, const LabelLegend& legend) {
  CV_Assert(labels.type() == CV_16UC1);
  // Colours of all ids up to the largest present, computed once.
  double max_value = 0.0;
  cv::minMaxLoc(labels, nullptr, &max_value);
  std::vector<cv::Vec3b> lut(static_cast<std::size_t>(max_value) + 1);
  for (std::size_t id = 0; id < lut.size(); ++id) {
    const auto rgb = legend.colorOf(static_cast<LabelId>(id));
    lut[id] = cv::Vec3b(rgb[0], rgb[1], rgb[2]);
  }
  cv::Mat rgb(labels.size(), CV_8UC3);
  for (int y = 0; y < labels.rows; ++y) {
    const uint16_t* in = labels.ptr<uint16_t>(y);
    cv::Vec3b* out = rgb.ptr<cv::Vec3b>(y);
    for (int x = 0; x < labels.cols; ++x) out[x] = lut[in[x]];
  }
  return rgb;
}

cv::Mat colorizeDepth(const cv::Mat& metres, float min_m, float max_m) {
  CV_Assert(metres.type() == CV_32FC1 && max_m > min_m);
  cv::Mat scaled;
  metres.convertTo(scaled, CV_8U, 255.0 / (max_m - min_m), -255.0 * min_m / (max_m - min_m));
  cv::Mat bgr;
  cv::applyColorMap(scaled, bgr, cv::COLORMAP_TURBO);
  const cv::Mat invalid = ~(metres > 0.0f);  // NaN compares false: invalid too
  bgr.setTo(cv::Scalar::all(0), invalid);
  return swapRedBlue(bgr);
}

}  // namespace semfuse::wire
