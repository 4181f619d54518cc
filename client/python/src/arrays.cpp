#include "arrays.hpp"

#include <cmath>
#include <string>

#include <opencv2/core.hpp>

#include "semfuse/core/camera_check.hpp"

namespace semfuse::python {
namespace {

py::dtype dtypeOf(int depth) {
  switch (depth) {
    case CV_8U:
      return py::dtype::of<uint8_t>();
    case CV_8S:
      return py::dtype::of<int8_t>();
    case CV_16U:
      return py::dtype::of<uint16_t>();
    case CV_16S:
      return py::dtype::of<int16_t>();
    case CV_32S:
      return py::dtype::of<int32_t>();
    case CV_32F:
      return py::dtype::of<float>();
    case CV_64F:
      return py::dtype::of<double>();
    default:
      throw std::runtime_error("image of OpenCV depth " + std::to_string(depth) + " has no numpy type");
  }
}

std::string describe(const py::array& a) {
  std::string shape = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
  if (a.ndim() == 1) shape += ",";
  return py::str(a.dtype()).cast<std::string>() + " array of shape " + shape + ")";
}

py::array asArray(const py::handle& object, const char* what) {
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(what) + " must be a numpy array, got " +
                         py::str(py::type::of(object).attr("__name__")).cast<std::string>());
  return py::reinterpret_borrow<py::array>(object);
}

// A C-contiguous array of T, converted (copied) when the array is of another type or layout.
template <class T>
py::array_t<T, py::array::c_style> contiguous(const py::array& a) {
  return py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
}

// Wraps a C-contiguous array's buffer as an image (no copy).
template <class T>
cv::Mat wrap(const py::array_t<T, py::array::c_style>& a, int type) {
  return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), type, const_cast<T*>(a.data()));
}

bool isInteger(const py::array& a) {
  const char kind = a.dtype().kind();
  return kind == 'i' || kind == 'u';
}
bool isFloat(const py::array& a) { return a.dtype().kind() == 'f'; }

}  // namespace

py::object imageToArray(const cv::Mat& image) {
  if (image.empty()) return py::none();
  auto* owned = new cv::Mat(image);  // shares the buffer, keeps its reference count
  py::capsule keep(owned, [](void* p) { delete static_cast<cv::Mat*>(p); });
  std::vector<py::ssize_t> shape{owned->rows, owned->cols};
  std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(owned->step[0]), static_cast<py::ssize_t>(owned->step[1])};
  if (owned->channels() > 1) {
    shape.push_back(owned->channels());
    strides.push_back(static_cast<py::ssize_t>(owned->elemSize1()));
  }
  return py::array(dtypeOf(owned->depth()), shape, strides, owned->data, keep);
}

cv::Mat depthFromArray(const py::handle& object, const char* what) {
  const py::array a = asArray(object, what);
  if (a.ndim() != 2) throw py::value_error(std::string(what) + " must be 2-D (rows, cols), got a " + describe(a));
  if (a.dtype().is(py::dtype::of<uint16_t>())) {
    cv::Mat metres;
    wrap(contiguous<uint16_t>(a), CV_16UC1).convertTo(metres, CV_32FC1, 0.001);
    return metres;
  }
  if (!isFloat(a))
    throw py::value_error(std::string(what) + " must be float metres or uint16 millimetres, got a " + describe(a));
  if (a.dtype().is(py::dtype::of<float>()) && (a.flags() & py::array::c_style)) {
    return wrap(py::array_t<float, py::array::c_style>::ensure(a), CV_32FC1);
  }
  return wrap(contiguous<float>(a), CV_32FC1).clone();  // the converted array dies here: copy it
}

cv::Mat colorFromArray(const py::handle& object, const char* what) {
  const py::array a = asArray(object, what);
  if (a.ndim() != 3 || a.shape(2) != 3 || !a.dtype().is(py::dtype::of<uint8_t>()))
    throw py::value_error(std::string(what) + " must be a (rows, cols, 3) uint8 RGB array, got a " + describe(a));
  const auto rgb = contiguous<uint8_t>(a);
  cv::Mat image(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_8UC3, const_cast<uint8_t*>(rgb.data()));
  // A strided or converted input made a temporary: the image must own its copy.
  return rgb.ptr() == a.ptr() ? image : image.clone();
}

namespace {
// A 2-D array of integers within uint16, copied as CV_16UC1; errors name `what`.
Result<cv::Mat> uint16ImageFromArray(const py::handle& object, const std::string& what) {
  if (!py::isinstance<py::array>(object))
    return makeError(
        ErrorCode::kInvalidArgument,
        what + " must be a numpy array, got " + py::str(py::type::of(object).attr("__name__")).cast<std::string>());
  const auto a = py::reinterpret_borrow<py::array>(object);
  if (a.ndim() != 2) return makeError(ErrorCode::kInvalidArgument, what + " must be 2-D, got a " + describe(a));
  if (!isInteger(a))
    return makeError(ErrorCode::kInvalidArgument, what + " must be integers (uint16), got a " + describe(a));
  if (a.size() == 0) return makeError(ErrorCode::kInvalidArgument, what + " are empty: " + describe(a));
  if (!a.dtype().is(py::dtype::of<uint16_t>())) {
    const auto low = a.attr("min")().cast<double>();
    const auto high = a.attr("max")().cast<double>();
    if (low < 0 || high > 65535)
      return makeError(ErrorCode::kInvalidArgument,
                       what + " range from " + py::repr(a.attr("min")()).cast<std::string>() + " to " +
                           py::repr(a.attr("max")()).cast<std::string>() + ", outside uint16 (" + describe(a) + ")");
  }
  return wrap(contiguous<uint16_t>(a), CV_16UC1).clone();
}
}  // namespace

Result<cv::Mat> labelsFromArray(const py::handle& object) { return uint16ImageFromArray(object, "labels"); }

Result<cv::Mat> instancesFromArray(const py::handle& object, const cv::Size& size) {
  auto ids = uint16ImageFromArray(object, "instances");
  if (!ids) return ids;
  if (ids.value().size() != size)
    return makeError(ErrorCode::kInvalidArgument, "instances are " + std::to_string(ids.value().rows) + "x" +
                                                      std::to_string(ids.value().cols) + " (rows x cols), the labels " +
                                                      std::to_string(size.height) + "x" + std::to_string(size.width));
  return ids;
}

Result<cv::Mat> confidenceFromArray(const py::handle& object, const cv::Size& size) {
  if (!py::isinstance<py::array>(object))
    return makeError(
        ErrorCode::kInvalidArgument,
        "confidence must be a numpy array, got " + py::str(py::type::of(object).attr("__name__")).cast<std::string>());
  const auto a = py::reinterpret_borrow<py::array>(object);
  if (a.ndim() != 2 || !isFloat(a))
    return makeError(ErrorCode::kInvalidArgument, "confidence must be a 2-D float array, got a " + describe(a));
  if (a.shape(0) != size.height || a.shape(1) != size.width)
    return makeError(ErrorCode::kInvalidArgument, "confidence is a " + describe(a) + ", the labels are " +
                                                      std::to_string(size.height) + "x" + std::to_string(size.width));
  cv::Mat confidence = wrap(contiguous<float>(a), CV_32FC1).clone();
  for (int r = 0; r < confidence.rows; ++r) {
    const float* row = confidence.ptr<float>(r);
    for (int c = 0; c < confidence.cols; ++c)
      if (!(row[c] >= 0.0F && row[c] <= 1.0F))
        return makeError(ErrorCode::kInvalidArgument, "confidence at row " + std::to_string(r) + ", column " +
                                                          std::to_string(c) + " is " + std::to_string(row[c]) +
                                                          ", outside [0, 1]");
  }
  return confidence;
}

Pose poseFromArray(const py::handle& object, const char* what) {
  const auto a = contiguous<double>(py::array::ensure(object));
  if (!a || a.ndim() != 2 || (a.shape(0) != 4 && a.shape(0) != 3) || a.shape(1) != 4)
    throw py::value_error(std::string(what) + " must be a 4x4 (or 3x4) camera-to-world matrix");
  Pose pose = Pose::Identity();
  for (int r = 0; r < a.shape(0); ++r)
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = a.at(r, c);
  if (Status ok = checkRigidPose(pose); !ok) throw py::value_error(std::string(what) + ": " + ok.error());
  return pose;
}

py::array poseToArray(const Pose& pose) {
  py::array_t<double> out({4, 4});
  auto m = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = pose.matrix()(r, c);
  return out;
}

std::vector<Eigen::Vector3d> pointsFromArray(const py::handle& object, const char* what) {
  auto a = contiguous<double>(py::array::ensure(object));
  if (a && a.ndim() == 1 && a.shape(0) == 3) a = contiguous<double>(a.reshape({1, 3}));
  if (!a || a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(std::string(what) + " must be an (N, 3) array of x, y, z in metres");
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    points[i] = {a.at(i, 0), a.at(i, 1), a.at(i, 2)};
    if (!points[i].allFinite())
      throw py::value_error(std::string(what) + ": point " + std::to_string(i) + " is not finite");
  }
  return points;
}

Eigen::Vector3d pointFromArray(const py::handle& object, const char* what) {
  const auto a = contiguous<double>(py::array::ensure(object));
  if (!a || a.ndim() != 1 || a.shape(0) != 3) throw py::value_error(std::string(what) + " must be 3 numbers x, y, z");
  Eigen::Vector3d p(a.at(0), a.at(1), a.at(2));
  if (!p.allFinite()) throw py::value_error(std::string(what) + " is not finite");
  return p;
}

py::array vectorToArray(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  for (int i = 0; i < 3; ++i) out.mutable_at(i) = v[i];
  return out;
}

}  // namespace semfuse::python
