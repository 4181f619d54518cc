#include "semfuse/wire/image_convert.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace semfuse::wire {
namespace {

TEST(ImageConvert, DepthUnitsAndMetres) {
  cv::Mat metres = (cv::Mat_<float>(1, 4) << 1.2345f, 0.0f, std::nanf(""), 80.0f);
  const cv::Mat mm = depthMetresToUnits(metres);
  EXPECT_EQ(mm.at<uint16_t>(0, 0), 1235);  // rounded
  EXPECT_EQ(mm.at<uint16_t>(0, 1), 0);
  EXPECT_EQ(mm.at<uint16_t>(0, 2), 0);
  EXPECT_EQ(mm.at<uint16_t>(0, 3), 0);  // beyond 65.535 m: invalid, not clamped
  const cv::Mat back = depthUnitsToMetres(mm);
  EXPECT_FLOAT_EQ(back.at<float>(0, 0), 1.235f);
  EXPECT_EQ(depthMetresToUnits(metres, 1.0 / 5000.0).at<uint16_t>(0, 0), 6173);  // TUM scale
}

TEST(ImageConvert, LabelsGetLegendColours) {
  const LabelLegend legend = *builtinLegend("synthetic");
  cv::Mat labels = (cv::Mat_<uint16_t>(1, 3) << 0, 5, 300);
  const cv::Mat rgb = colorizeLabels(labels, legend);
  ASSERT_EQ(rgb.type(), CV_8UC3);
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 1), cv::Vec3b(220, 40, 60));  // chair
  const auto unknown = legend.colorOf(300);
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 2), cv::Vec3b(unknown[0], unknown[1], unknown[2]));
}

TEST(ImageConvert, DepthColourisationBlacksOutInvalidPixels) {
  cv::Mat metres = (cv::Mat_<float>(1, 3) << 0.0f, 1.0f, 4.0f);
  const cv::Mat rgb = colorizeDepth(metres, 0.5f, 4.5f);
  EXPECT_EQ(rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
  EXPECT_NE(rgb.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 0, 0));
  EXPECT_NE(rgb.at<cv::Vec3b>(0, 1), rgb.at<cv::Vec3b>(0, 2));
}

}  // namespace
}  // namespace semfuse::wire
