#include "semfuse/wire/ros_codec.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstring>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/core/camera_check.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/image_convert.hpp"
#include "semfuse/wire/jpeg_decode.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::wire {
namespace {

struct RosEncoding {
  const char* name;
  int cv_type;  // type of the raw pixels
  int channels;
  bool swap_to_rgb;  // BGR(A) order on the wire
};

const RosEncoding kRosEncodings[] = {
    {"16UC1", CV_16UC1, 1, false}, {"mono16", CV_16UC1, 1, false}, {"32FC1", CV_32FC1, 1, false},
    {"mono8", CV_8UC1, 1, false},  {"8UC1", CV_8UC1, 1, false},    {"rgb8", CV_8UC3, 3, false},
    {"bgr8", CV_8UC3, 3, true},    {"8UC3", CV_8UC3, 3, false},    {"rgba8", CV_8UC4, 4, false},
    {"bgra8", CV_8UC4, 4, true},
};

const RosEncoding* findEncoding(const std::string& name) {
  for (const RosEncoding& encoding : kRosEncodings) {
    if (name == encoding.name) return &encoding;
  }
  return nullptr;
}

}  // namespace

const std::vector<std::string>& rosImageEncodings() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const RosEncoding& encoding : kRosEncodings) list.emplace_back(encoding.name);
    return list;
  }();
  return names;
}

Result<cv::Mat> imageToMat(const sensor_msgs_msg_dds__Image_& msg) {
  const std::string name = stringOf(msg.encoding);
  if (Status s = validateEncoding("image", name, rosImageEncodings()); !s) return makeError(s.error());
  const RosEncoding& encoding = *findEncoding(name);
  if (Status s = validateImageSize("image", msg.width, msg.height); !s) return makeError(s.error());
  if (Status s = validateSequence("image", msg.data._length, msg.data._maximum, msg.data._buffer); !s) {
    return makeError(s.error());
  }
  const std::size_t pixel_bytes = CV_ELEM_SIZE(encoding.cv_type);
  const std::size_t row_bytes = msg.width * pixel_bytes;
  if (msg.step < row_bytes) {
    return makeError("image: step " + std::to_string(msg.step) + " shorter than a row of " + std::to_string(msg.width) +
                     " " + name + " pixels (" + std::to_string(row_bytes) + " bytes)");
  }
  const uint64_t expected = static_cast<uint64_t>(msg.step) * msg.height;
  if (msg.data._length != expected) {
    return makeError("image: " + std::to_string(msg.data._length) + " bytes for " + std::to_string(msg.width) + "x" +
                     std::to_string(msg.height) + " " + name + " with step " + std::to_string(msg.step) +
                     ", expected " + std::to_string(expected));
  }
  cv::Mat image(static_cast<int>(msg.height), static_cast<int>(msg.width), encoding.cv_type);
  for (int y = 0; y < image.rows; ++y) {
    std::memcpy(image.ptr(y), msg.data._buffer + static_cast<std::size_t>(y) * msg.step, row_bytes);
  }
  const std::size_t depth_bytes = CV_ELEM_SIZE1(encoding.cv_type);
  if (msg.is_bigendian && depth_bytes > 1) {
    for (int y = 0; y < image.rows; ++y) {
      uint8_t* row = image.ptr(y);
      for (std::size_t i = 0; i < row_bytes; i += depth_bytes) std::reverse(row + i, row + i + depth_bytes);
    }
  }
  if (encoding.channels == 4) {
    cv::Mat rgb;
    cv::cvtColor(image, rgb, encoding.swap_to_rgb ? cv::COLOR_BGRA2RGB : cv::COLOR_RGBA2RGB);
    return rgb;
  }
  return encoding.swap_to_rgb ? swapRedBlue(image) : image;
}

Result<cv::Mat> depthImageToMetres(const sensor_msgs_msg_dds__Image_& msg) {
  const std::string name = stringOf(msg.encoding);
  if (Status s = validateEncoding("depth image", name, {"16UC1", "mono16", "32FC1"}); !s) return makeError(s.error());
  auto image = imageToMat(msg);
  if (!image) return image;
  if (image.value().type() == CV_32FC1) return image;
  return depthUnitsToMetres(image.value(), 0.001);
}

Result<OwnedImage> matToImage(const cv::Mat& image, const std::string& encoding, Stamp stamp,
                              const std::string& frame_id) {
  const RosEncoding* target = findEncoding(encoding);
  if (target == nullptr) return makeError(validateEncoding("image", encoding, rosImageEncodings()).error());
  if (image.type() != target->cv_type) {
    return makeError("image: a " + typeName(image.type()) + " image cannot be sent as " + encoding + " (needs " +
                     typeName(target->cv_type) + ")");
  }
  if (Status s = validateImageSize("image", image.cols, image.rows); !s) return makeError(s.error());
  const cv::Mat packed = target->swap_to_rgb ? swapRedBlue(image) : (image.isContinuous() ? image : image.clone());
  OwnedImage owned;
  auto& msg = owned.msg();
  fillHeader(owned, msg.header, stamp, frame_id);
  msg.height = static_cast<uint32_t>(image.rows);
  msg.width = static_cast<uint32_t>(image.cols);
  msg.encoding = owned.keepString(encoding);
  msg.is_bigendian = 0;
  msg.step = static_cast<uint32_t>(image.cols * image.elemSize());
  owned.keepSequence(msg.data, std::vector<uint8_t>(packed.data, packed.data + packed.total() * packed.elemSize()));
  return owned;
}

Result<cv::Mat> compressedImageToMat(const sensor_msgs_msg_dds__CompressedImage_& msg) {
  std::string format = stringOf(msg.format);
  std::transform(format.begin(), format.end(), format.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (format.find("compresseddepth") != std::string::npos) {
    return makeError("compressed image: format '" + format +
                     "' is compressedDepth, which only the compressed depth input reads");
  }
  const bool png = format.find("png") != std::string::npos;
  const bool jpeg = format.find("jpeg") != std::string::npos || format.find("jpg") != std::string::npos;
  if (!png && !jpeg) return makeError("compressed image: unknown format '" + format + "' (known: jpeg, png)");
  if (Status s = validateSequence("compressed image", msg.data._length, msg.data._maximum, msg.data._buffer); !s) {
    return makeError(s.error());
  }
  if (msg.data._length == 0) return makeError("compressed image: empty payload");
  // The declared size is bounded before decoding: the decoder allocates what the header says.
  auto declared =
      png ? pngDeclaredSize(msg.data._buffer, msg.data._length) : jpegDeclaredSize(msg.data._buffer, msg.data._length);
  if (!declared) {
    return makeError(std::string("compressed image: ") + (png ? "PNG" : "JPEG") +
                     " payload does not decode: " + declared.error());
  }
  if (Status s = validateImageSize("compressed image", declared.value().width, declared.value().height); !s) {
    return makeError(s.error());
  }
  if (png) {
    if (Status whole = pngChunksComplete(msg.data._buffer, msg.data._length); !whole)
      return makeError("compressed image: PNG payload does not decode: " + whole.error());
  }
  if (jpeg) {
    auto decoded = decodeJpegRgbOrGrey(msg.data._buffer, msg.data._length, declared.value());
    if (!decoded) return makeError("compressed image: " + decoded.error());
    return decoded;
  }
  const cv::Mat payload(1, static_cast<int>(msg.data._length), CV_8UC1, msg.data._buffer);
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(payload, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  if (decoded.empty())
    return makeError(std::string("compressed image: ") + (png ? "PNG" : "JPEG") + " payload does not decode");
  if (Status s = validateImageSize("compressed image", decoded.cols, decoded.rows); !s) return makeError(s.error());
  return decoded.type() == CV_8UC3 ? swapRedBlue(decoded) : decoded;
}

Result<PinholeIntrinsics> intrinsicsFromCameraInfo(const sensor_msgs_msg_dds__CameraInfo_& msg) {
  if (Status s = validateImageSize("camera info", msg.width, msg.height); !s) return makeError(s.error());
  PinholeIntrinsics intrinsics{
      static_cast<int>(msg.width), static_cast<int>(msg.height), msg.k[0], msg.k[4], msg.k[2], msg.k[5]};
  if (Status s = checkIntrinsics(intrinsics, kMaxImageSide); !s) return s.errorInfo().prefixed("camera info: ");
  return intrinsics;
}

OwnedCameraInfo cameraInfoFromIntrinsics(const PinholeIntrinsics& k, Stamp stamp, const std::string& frame_id) {
  OwnedCameraInfo owned;
  auto& msg = owned.msg();
  fillHeader(owned, msg.header, stamp, frame_id);
  msg.width = static_cast<uint32_t>(k.width);
  msg.height = static_cast<uint32_t>(k.height);
  msg.distortion_model = owned.keepString("plumb_bob");
  owned.keepSequence(msg.d, std::vector<double>(5, 0.0));
  const double K[9] = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double P[12] = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  std::copy(K, K + 9, msg.k);
  std::copy(R, R + 9, msg.r);
  std::copy(P, P + 12, msg.p);
  return owned;
}

Result<Pose> poseFromTransform(const geometry_msgs_msg_dds__Transform_& transform) {
  const auto& q = transform.rotation;
  const auto& t = transform.translation;
  const Eigen::Quaterniond quaternion(q.w, q.x, q.y, q.z);
  const double norm = quaternion.norm();
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3) {
    return makeError("transform: quaternion norm " + std::to_string(norm) + " is not 1");
  }
  if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
    return makeError("transform: non-finite translation");
  }
  Pose pose = Pose::Identity();
  pose.linear() = quaternion.normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(t.x, t.y, t.z);
  return pose;
}

OwnedTransform transformFromPose(const Pose& pose, Stamp stamp, const std::string& frame_id,
                                 const std::string& child_frame_id) {
  OwnedTransform owned;
  auto& msg = owned.msg();
  fillHeader(owned, msg.header, stamp, frame_id);
  msg.child_frame_id = owned.keepString(child_frame_id);
  const Eigen::Quaterniond q(pose.linear());
  msg.transform.rotation = {q.x(), q.y(), q.z(), q.w()};
  msg.transform.translation = {pose.translation().x(), pose.translation().y(), pose.translation().z()};
  return owned;
}

Stamp stampNow() {
  const auto since_epoch = std::chrono::system_clock::now().time_since_epoch();
  const auto nanos = std::chrono::duration_cast<std::chrono::nanoseconds>(since_epoch).count();
  return {static_cast<int32_t>(nanos / 1000000000LL), static_cast<uint32_t>(nanos % 1000000000LL)};
}

}  // namespace semfuse::wire
