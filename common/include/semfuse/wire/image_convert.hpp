#pragma once
// Conversions between the image forms semfuse meets: depth in integer units (millimetres for
// Kinect-style sensors and ROS 16UC1) vs float metres, RGB vs OpenCV's BGR, and display images.
#include <opencv2/core/mat.hpp>

#include "semfuse/core/legend.hpp"

namespace semfuse::wire {

// CV_16UC1 units -> CV_32FC1 metres; 0 stays 0 (invalid).
cv::Mat depthUnitsToMetres(const cv::Mat& units, double metres_per_unit = 0.001);
// CV_32FC1 metres -> CV_16UC1 units, rounded; invalid (0, NaN, negative) and depths beyond the
// 16-bit range become 0 rather than a wrong clamped value.
cv::Mat depthMetresToUnits(const cv::Mat& metres, double metres_per_unit = 0.001);

// Swaps the first and third channel of an 8-bit 3-channel image (RGB <-> BGR).
cv::Mat swapRedBlue(const cv::Mat& image);

// CV_16UC1 label image -> CV_8UC3 RGB with the legend's colours.
cv::Mat colorizeLabels(const cv::Mat& labels, const LabelLegend& legend);
// CV_32FC1 metres -> CV_8UC3 RGB (turbo colour map from min_m to max_m; invalid pixels black).
cv::Mat colorizeDepth(const cv::Mat& metres, float min_m = 0.3f, float max_m = 5.0f);

}  // namespace semfuse::wire
