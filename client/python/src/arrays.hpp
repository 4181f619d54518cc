#pragma once
// Between numpy arrays and the client library's types: images (cv::Mat), poses (4x4), points.
// Images go to Python without a copy (the array keeps the cv::Mat's buffer alive); arrays
// coming from Python are checked (shape, dtype, range) with a message that names the argument.
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::python {

namespace py = pybind11;

// The image as an array sharing its buffer: (rows, cols) or (rows, cols, channels), of the
// element type of the image's depth. An empty image gives None.
py::object imageToArray(const cv::Mat& image);

// A flat vector as an array of `shape` (its product must be the vector's size), taking the vector.
template <class T>
py::array vectorToArray(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), free);
}

// A (rows, cols) float array in metres (float32 or float64) or millimetres (uint16) as a CV_32FC1
// image in metres. Float32 C-contiguous arrays are wrapped without a copy: the result is valid
// while `array` lives. Raises ValueError naming `what` for anything else.
cv::Mat depthFromArray(const py::handle& array, const char* what);
// A (rows, cols, 3) uint8 RGB array as CV_8UC3, wrapped without a copy when C-contiguous.
cv::Mat colorFromArray(const py::handle& array, const char* what);

// A segmenter's labels: a 2-D integer array whose values fit uint16, copied into a CV_16UC1
// image the Segmentation owns. An error (not an exception) says what is wrong.
Result<cv::Mat> labelsFromArray(const py::handle& array);
// A panoptic segmenter's instance ids (0 = no instance): integers within uint16 of the labels'
// `size`, copied as CV_16UC1.
Result<cv::Mat> instancesFromArray(const py::handle& array, const cv::Size& size);
// A segmenter's confidence: a 2-D float array of `size`, values in [0, 1], copied as CV_32FC1.
Result<cv::Mat> confidenceFromArray(const py::handle& array, const cv::Size& size);

// camera-to-world poses: a 4x4 (or 3x4) array of finite numbers with a rotation block, as an
// isometry. Raises ValueError naming `what`.
Pose poseFromArray(const py::handle& array, const char* what);
py::array poseToArray(const Pose& pose);

// (N, 3) points in metres; raises ValueError naming `what`.
std::vector<Eigen::Vector3d> pointsFromArray(const py::handle& array, const char* what);
Eigen::Vector3d pointFromArray(const py::handle& array, const char* what);
py::array vectorToArray(const Eigen::Vector3d& v);

}  // namespace semfuse::python
