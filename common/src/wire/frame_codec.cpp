#include "semfuse/wire/frame_codec.hpp"

#include <cmath>
#include <cstring>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "semfuse/core/camera_check.hpp"
#include "semfuse/wire/image_convert.hpp"
#include "semfuse/wire/jpeg_decode.hpp"
#include "semfuse/wire/rvl_codec.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::wire {
namespace {

std::vector<uint8_t> bytesOf(const cv::Mat& image) {
  const cv::Mat continuous = image.isContinuous() ? image : image.clone();
  const auto* begin = continuous.ptr<uint8_t>();
  return std::vector<uint8_t>(begin, begin + continuous.total() * continuous.elemSize());
}

Result<std::vector<uint8_t>> encodeImage(const std::string& extension, const cv::Mat& image,
                                         const std::vector<int>& params) {
  std::vector<uint8_t> bytes;
  try {
    if (!cv::imencode(extension, image, bytes, params)) return makeError("encoder " + extension + " failed");
  } catch (const cv::Exception& e) {
    return makeError("encoder " + extension + " failed: " + e.what());
  }
  return bytes;
}

Result<std::vector<uint8_t>> encodeDepth(const cv::Mat& metres, const FrameEncoding& encoding) {
  if (encoding.depth == "32FC1") return bytesOf(metres);
  if (!(std::isfinite(encoding.depth_scale) && encoding.depth_scale > 0.0)) {
    return makeError("depth_scale must be finite and > 0 for " + encoding.depth + ", got " +
                     std::to_string(encoding.depth_scale));
  }
  const cv::Mat units = depthMetresToUnits(metres, encoding.depth_scale);
  if (encoding.depth == "16UC1") return bytesOf(units);
  if (encoding.depth == "rvl") return encodeRvl(units);
  return encodeImage(".png", units, {cv::IMWRITE_PNG_COMPRESSION, encoding.png_compression});
}

Result<std::vector<uint8_t>> encodeColor(const cv::Mat& rgb, const FrameEncoding& encoding) {
  if (encoding.color == "rgb8") return bytesOf(rgb);
  const cv::Mat bgr = swapRedBlue(rgb);  // OpenCV's encoders and "bgr8" want BGR
  if (encoding.color == "bgr8") return bytesOf(bgr);
  if (encoding.color == "jpeg") return encodeImage(".jpg", bgr, {cv::IMWRITE_JPEG_QUALITY, encoding.jpeg_quality});
  return encodeImage(".png", bgr, {cv::IMWRITE_PNG_COMPRESSION, encoding.png_compression});
}

// A generated uint8 sequence as a read-only Mat header, after checking it is whole.
const uint8_t* sequenceData(const dds_sequence_uint8& seq) { return seq._buffer; }

Result<cv::Mat> decodeDepth(const semfuse_msg_dds__Frame_& msg, uint32_t width, uint32_t height) {
  const std::string encoding = stringOf(msg.depth_encoding);
  if (Status s = validateEncoding("depth", encoding, depthEncodings()); !s) return makeError(s.error());
  if (Status s = validateSequence("depth", msg.depth._length, msg.depth._maximum, msg.depth._buffer); !s) {
    return makeError(s.error());
  }
  const std::size_t bytes = msg.depth._length;
  const int w = static_cast<int>(width), h = static_cast<int>(height);
  if (encoding == "32FC1") {
    if (Status s = validateDataSize("depth", bytes, width, height, encoding, 4); !s) return makeError(s.error());
    cv::Mat metres(h, w, CV_32FC1);
    std::memcpy(metres.data, sequenceData(msg.depth), bytes);  // copy: the buffer may be unaligned
    for (int y = 0; y < h; ++y) {
      const float* row = metres.ptr<float>(y);
      for (int x = 0; x < w; ++x) {
        if (row[x] < 0.0f || std::isinf(row[x])) {
          return makeError("depth: value " + std::to_string(row[x]) + " at (" + std::to_string(x) + ", " +
                           std::to_string(y) + ") is negative or infinite (0 or NaN mark invalid pixels)");
        }
      }
    }
    return metres;
  }
  if (!(std::isfinite(msg.depth_scale) && msg.depth_scale > 0.0f)) {
    return makeError("depth: depth_scale must be finite and > 0 for " + encoding + ", got " +
                     std::to_string(msg.depth_scale));
  }
  cv::Mat units;
  if (encoding == "16UC1") {
    if (Status s = validateDataSize("depth", bytes, width, height, encoding, 2); !s) return makeError(s.error());
    units.create(h, w, CV_16UC1);
    std::memcpy(units.data, sequenceData(msg.depth), bytes);
  } else if (encoding == "rvl") {
    auto declared = rvlDeclaredSize(sequenceData(msg.depth), bytes);
    if (!declared) return makeError("depth: " + declared.error());
    if (declared.value() != cv::Size(w, h)) {
      return makeError("depth: RVL declares " + std::to_string(declared.value().width) + "x" +
                       std::to_string(declared.value().height) + ", frame declares " + std::to_string(w) + "x" +
                       std::to_string(h));
    }
    auto decoded = decodeRvl(sequenceData(msg.depth), bytes, cv::Size(w, h));
    if (!decoded) return makeError("depth: " + decoded.error());
    units = std::move(decoded).value();
  } else {  // png16
    auto declared = pngDeclaredSize(sequenceData(msg.depth), bytes);
    if (!declared) return makeError("depth: PNG payload does not decode: " + declared.error());
    if (Status whole = pngChunksComplete(sequenceData(msg.depth), bytes); !whole)
      return makeError("depth: PNG payload does not decode: " + whole.error());
    if (declared.value() != cv::Size(w, h)) {
      return makeError("depth: PNG declares " + std::to_string(declared.value().width) + "x" +
                       std::to_string(declared.value().height) + ", frame declares " + std::to_string(w) + "x" +
                       std::to_string(h));
    }
    const cv::Mat payload(1, static_cast<int>(bytes), CV_8UC1, const_cast<uint8_t*>(sequenceData(msg.depth)));
    units = cv::imdecode(payload, cv::IMREAD_ANYDEPTH);
    if (Status s = validateDecodedImage("depth", "PNG", units, width, height, CV_16UC1); !s)
      return makeError(s.error());
  }
  return depthUnitsToMetres(units, msg.depth_scale);
}

Result<cv::Mat> decodeColor(const semfuse_msg_dds__Frame_& msg, uint32_t width, uint32_t height) {
  const std::string encoding = stringOf(msg.color_encoding);
  if (Status s = validateEncoding("color", encoding, colorEncodings()); !s) return makeError(s.error());
  if (encoding.empty()) {
    if (msg.color._length != 0) {
      return makeError("color: " + std::to_string(msg.color._length) + " bytes of colour with encoding \"\" (none)");
    }
    return cv::Mat();
  }
  if (Status s = validateSequence("color", msg.color._length, msg.color._maximum, msg.color._buffer); !s) {
    return makeError(s.error());
  }
  const std::size_t bytes = msg.color._length;
  const int w = static_cast<int>(width), h = static_cast<int>(height);
  if (encoding == "rgb8" || encoding == "bgr8") {
    if (Status s = validateDataSize("color", bytes, width, height, encoding, 3); !s) return makeError(s.error());
    cv::Mat image(h, w, CV_8UC3);
    std::memcpy(image.data, sequenceData(msg.color), bytes);
    return encoding == "rgb8" ? image : swapRedBlue(image);
  }
  const std::string format = encoding == "jpeg" ? "JPEG" : "PNG";
  // The size the payload declares, checked before decoding: the decoder allocates what it says.
  auto declared = encoding == "png" ? pngDeclaredSize(sequenceData(msg.color), bytes)
                                    : jpegDeclaredSize(sequenceData(msg.color), bytes);
  if (!declared) return makeError("color: " + format + " payload does not decode: " + declared.error());
  if (declared.value() != cv::Size(w, h)) {
    return makeError("color: " + format + " declares " + std::to_string(declared.value().width) + "x" +
                     std::to_string(declared.value().height) + ", frame declares " + std::to_string(w) + "x" +
                     std::to_string(h));
  }
  if (bytes == 0) return makeError("color: empty " + format + " payload");
  if (encoding == "png") {
    if (Status whole = pngChunksComplete(sequenceData(msg.color), bytes); !whole)
      return makeError("color: PNG payload does not decode: " + whole.error());
  }
  if (encoding == "jpeg") {
    auto rgb = decodeJpegRgb(sequenceData(msg.color), bytes, cv::Size(w, h));
    if (!rgb) return makeError("color: " + rgb.error());
    return rgb;
  }
  const cv::Mat payload(1, static_cast<int>(bytes), CV_8UC1, const_cast<uint8_t*>(sequenceData(msg.color)));
  cv::Mat bgr;
  try {
    bgr = cv::imdecode(payload, cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    bgr.release();  // reported as "does not decode" below
  }
  if (Status s = validateDecodedImage("color", format, bgr, width, height, CV_8UC3); !s) return makeError(s.error());
  return swapRedBlue(bgr);
}

}  // namespace

const std::vector<std::string>& depthEncodings() {
  static const std::vector<std::string> names = {"16UC1", "32FC1", "png16", "rvl"};
  return names;
}

const std::vector<std::string>& colorEncodings() {
  static const std::vector<std::string> names = {"", "rgb8", "bgr8", "jpeg", "png"};
  return names;
}

void poseToRowMajor(const Pose& pose, double out[12]) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) out[r * 4 + c] = pose.matrix()(r, c);
  }
}

Pose poseFromRowMajor(const double in[12]) {
  Pose pose = Pose::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = in[r * 4 + c];
  }
  return pose;
}

Result<EncodedFrame> encodeFrame(const Frame& frame, const FrameEncoding& encoding) {
  if (frame.depth.type() != CV_32FC1) {
    return makeError("encodeFrame: depth must be CV_32FC1 metres, got " + typeName(frame.depth.type()));
  }
  if (Status s = validateImageSize("depth", frame.depth.cols, frame.depth.rows); !s) return makeError(s.error());
  // The camera the message will carry (its size is the depth's): a sender learns at once what
  // decodeFrame would refuse.
  PinholeIntrinsics sent = frame.intrinsics;
  sent.width = frame.depth.cols;
  sent.height = frame.depth.rows;
  if (Status s = checkIntrinsics(sent, kMaxImageSide); !s) return s.errorInfo();
  if (frame.camera_to_world) {
    if (Status s = checkRigidPose(*frame.camera_to_world); !s) return s.errorInfo();
  }
  // Colour encoding "" sends depth only, even for a frame that has colour.
  const bool has_color = !frame.color.empty() && !encoding.color.empty();
  if (has_color && (frame.color.type() != CV_8UC3 || frame.color.size() != frame.depth.size())) {
    return makeError("encodeFrame: colour must be CV_8UC3 RGB of the depth's size, got " +
                     typeName(frame.color.type()) + " " + std::to_string(frame.color.cols) + "x" +
                     std::to_string(frame.color.rows));
  }
  if (Status s = validateEncoding("depth", encoding.depth, depthEncodings()); !s) return makeError(s.error());
  const std::string color_encoding = has_color ? encoding.color : "";
  if (Status s = validateEncoding("color", color_encoding, colorEncodings()); !s) return makeError(s.error());

  EncodedFrame encoded;
  semfuse_msg_dds__Frame_& msg = encoded.msg();
  msg.header.stamp.sec = frame.stamp.sec;
  msg.header.stamp.nanosec = frame.stamp.nanosec;
  msg.header.frame_id = encoded.keepString(frame.frame_id);
  msg.camera_id = encoded.keepString(frame.camera_id);
  msg.seq = frame.seq;
  msg.intrinsics.width = static_cast<uint32_t>(frame.depth.cols);
  msg.intrinsics.height = static_cast<uint32_t>(frame.depth.rows);
  msg.intrinsics.fx = frame.intrinsics.fx;
  msg.intrinsics.fy = frame.intrinsics.fy;
  msg.intrinsics.cx = frame.intrinsics.cx;
  msg.intrinsics.cy = frame.intrinsics.cy;

  msg.depth_encoding = encoded.keepString(encoding.depth);
  msg.depth_scale = encoding.depth == "32FC1" ? 1.0f : static_cast<float>(encoding.depth_scale);
  auto depth = encodeDepth(frame.depth, encoding);
  if (!depth) return makeError("depth: " + depth.error());
  encoded.keepSequence(msg.depth, std::move(depth).value());

  msg.color_encoding = encoded.keepString(color_encoding);
  if (has_color) {
    auto color = encodeColor(frame.color, encoding);
    if (!color) return makeError("color: " + color.error());
    encoded.keepSequence(msg.color, std::move(color).value());
  } else {
    encoded.keepSequence(msg.color, std::vector<uint8_t>{});
  }

  msg.has_pose = frame.camera_to_world.has_value();
  if (msg.has_pose) poseToRowMajor(*frame.camera_to_world, msg.camera_to_world);
  return encoded;
}

Result<Frame> decodeFrame(const semfuse_msg_dds__Frame_& msg) {
  Frame frame;
  frame.camera_id = stringOf(msg.camera_id);
  if (frame.camera_id.empty()) return makeError("frame: empty camera_id");
  frame.seq = msg.seq;
  frame.stamp = {msg.header.stamp.sec, msg.header.stamp.nanosec};
  frame.frame_id = stringOf(msg.header.frame_id);
  const auto& k = msg.intrinsics;
  // Bounds first, as unsigned values: a huge width must not turn negative in an int.
  if (Status s = validateImageSize("frame", k.width, k.height); !s) return makeError(s.error());
  frame.intrinsics = {static_cast<int>(k.width), static_cast<int>(k.height), k.fx, k.fy, k.cx, k.cy};
  if (Status s = checkIntrinsics(frame.intrinsics, kMaxImageSide); !s) return s.errorInfo();

  auto depth = decodeDepth(msg, k.width, k.height);
  if (!depth) return makeError(depth.error());
  frame.depth = std::move(depth).value();
  auto color = decodeColor(msg, k.width, k.height);
  if (!color) return makeError(color.error());
  frame.color = std::move(color).value();

  if (msg.has_pose) {
    const Pose pose = poseFromRowMajor(msg.camera_to_world);
    if (Status s = checkRigidPose(pose); !s) return s.errorInfo();
    frame.camera_to_world = pose;
  }
  return frame;
}

}  // namespace semfuse::wire
