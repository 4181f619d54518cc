#pragma once
// Image and text file reading shared by the dataset readers (private to semfuse_datasets).
#include <filesystem>
#include <string>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::datasets::detail {

// Reads a 16-bit single-channel PNG and converts it to CV_32FC1 metres. Raw 0 is invalid (0 m);
// with saturated_is_invalid, raw 65535 too (7-Scenes writes it where the sensor gave no depth).
Result<cv::Mat> readDepthAsMetres(const std::filesystem::path& file, double metres_per_unit, bool saturated_is_invalid);

// Reads a colour image as CV_8UC3 in RGB order (OpenCV decodes to BGR).
Result<cv::Mat> readColorAsRgb(const std::filesystem::path& file);

// Size of an image without keeping its pixels (the readers need it once, for the intrinsics).
Result<cv::Size> readImageSize(const std::filesystem::path& file);

Stamp stampFromSeconds(double seconds);

}  // namespace semfuse::datasets::detail
