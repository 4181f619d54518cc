#include "wire_convert.hpp"

#include <cmath>
#include <cstring>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace semfuse::client::wire {
namespace {

std::string str(const char* s) { return s ? std::string(s) : std::string(); }

template <class Sequence>
void setBytes(Sequence& seq, const std::vector<uchar>& bytes) {
  dds::setSequence(seq, bytes.data(), bytes.size());
}

// Copies a continuous Mat's pixels into a byte sequence.
void setPixels(dds_sequence_uint8& seq, const cv::Mat& mat) {
  const cv::Mat continuous = mat.isContinuous() ? mat : mat.clone();
  dds::setSequence(seq, continuous.data, continuous.total() * continuous.elemSize());
}

// Metres (0/NaN invalid) -> millimetres, 0 where invalid or beyond the 16-bit range.
cv::Mat toMillimetres(const cv::Mat& depth) {
  cv::Mat mm(depth.size(), CV_16UC1);
  depth.forEach<float>([&](float d, const int* p) {
    const float v = std::isfinite(d) && d > 0.0F ? std::round(d * 1000.0F) : 0.0F;
    mm.at<uint16_t>(p[0], p[1]) = v < 65535.0F ? static_cast<uint16_t>(v) : 0;
  });
  return mm;
}

Result<cv::Mat> wrapBytes(const dds_sequence_uint8& seq, int rows, int cols, int type) {
  const std::size_t expected = static_cast<std::size_t>(rows) * cols * CV_ELEM_SIZE(type);
  if (seq._length != expected) {
    return makeError("image has " + std::to_string(seq._length) + " bytes, expected " +
                     std::to_string(expected));
  }
  cv::Mat mat(rows, cols, type);
  if (expected > 0) std::memcpy(mat.data, seq._buffer, expected);
  return mat;
}

Result<cv::Mat> decodeDepth(const semfuse_msg_dds__Frame_& msg, int rows, int cols) {
  const std::string encoding = str(msg.depth_encoding);
  cv::Mat units;
  if (encoding == "32FC1") {
    auto mat = wrapBytes(msg.depth, rows, cols, CV_32FC1);
    if (!mat) return mat;
    return std::move(mat).value();
  }
  if (encoding == "16UC1") {
    auto mat = wrapBytes(msg.depth, rows, cols, CV_16UC1);
    if (!mat) return mat;
    units = mat.value();
  } else if (encoding == "png16") {
    const cv::Mat bytes(1, static_cast<int>(msg.depth._length), CV_8UC1, msg.depth._buffer);
    units = cv::imdecode(bytes, cv::IMREAD_ANYDEPTH);
    if (units.empty() || units.type() != CV_16UC1 || units.rows != rows || units.cols != cols) {
      return makeError("depth PNG does not decode to a " + std::to_string(cols) + "x" +
                       std::to_string(rows) + " 16-bit image");
    }
  } else {
    return makeError("unknown depth encoding '" + encoding + "'");
  }
  cv::Mat metres;
  units.convertTo(metres, CV_32FC1, msg.depth_scale);
  return metres;
}

Result<cv::Mat> decodeColor(const semfuse_msg_dds__Frame_& msg, int rows, int cols) {
  const std::string encoding = str(msg.color_encoding);
  if (encoding.empty()) return cv::Mat();
  if (encoding == "rgb8") return wrapBytes(msg.color, rows, cols, CV_8UC3);
  cv::Mat rgb;
  if (encoding == "bgr8") {
    auto bgr = wrapBytes(msg.color, rows, cols, CV_8UC3);
    if (!bgr) return bgr;
    cv::cvtColor(bgr.value(), rgb, cv::COLOR_BGR2RGB);
    return rgb;
  }
  if (encoding != "jpeg" && encoding != "png") {
    return makeError("unknown colour encoding '" + encoding + "'");
  }
  const cv::Mat bytes(1, static_cast<int>(msg.color._length), CV_8UC1, msg.color._buffer);
  const cv::Mat bgr = cv::imdecode(bytes, cv::IMREAD_COLOR);
  if (bgr.empty()) return makeError("colour " + encoding + " does not decode");
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

}  // namespace

void poseToArray(const Pose& pose, double out[12]) {
  const Eigen::Matrix<double, 3, 4> m = pose.matrix().topRows<3>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out[r * 4 + c] = m(r, c);
}

Pose poseFromArray(const double in[12]) {
  Pose pose = Pose::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = in[r * 4 + c];
  return pose;
}

Status encodeFrame(const Frame& frame, const FrameEncoding& encoding,
                   semfuse_msg_dds__Frame_& out) {
  if (frame.depth.empty() || frame.depth.type() != CV_32FC1) {
    return makeError("frame depth must be a non-empty CV_32FC1 image");
  }
  if (!frame.color.empty() && (frame.color.type() != CV_8UC3 || frame.color.size() != frame.depth.size())) {
    return makeError("frame colour must be CV_8UC3 of the depth image's size");
  }
  out.header.stamp.sec = frame.stamp.sec;
  out.header.stamp.nanosec = frame.stamp.nanosec;
  dds::setString(out.header.frame_id, frame.frame_id);
  dds::setString(out.camera_id, frame.camera_id);
  out.seq = frame.seq;
  out.intrinsics.width = static_cast<uint32_t>(frame.depth.cols);
  out.intrinsics.height = static_cast<uint32_t>(frame.depth.rows);
  out.intrinsics.fx = frame.intrinsics.fx;
  out.intrinsics.fy = frame.intrinsics.fy;
  out.intrinsics.cx = frame.intrinsics.cx;
  out.intrinsics.cy = frame.intrinsics.cy;

  switch (encoding.depth) {
    case DepthEncoding::kRawFloat:
      dds::setString(out.depth_encoding, "32FC1");
      out.depth_scale = 1.0F;
      setPixels(out.depth, frame.depth);
      break;
    case DepthEncoding::kRaw16:
      dds::setString(out.depth_encoding, "16UC1");
      out.depth_scale = 0.001F;
      setPixels(out.depth, toMillimetres(frame.depth));
      break;
    case DepthEncoding::kPng16: {
      std::vector<uchar> png;
      // Level 1: nearly all of PNG's gain on depth images at a fraction of the default's time.
      if (!cv::imencode(".png", toMillimetres(frame.depth), png, {cv::IMWRITE_PNG_COMPRESSION, 1})) {
        return makeError("PNG encoding of the depth image failed");
      }
      dds::setString(out.depth_encoding, "png16");
      out.depth_scale = 0.001F;
      setBytes(out.depth, png);
      break;
    }
  }

  const ColorEncoding color = frame.color.empty() ? ColorEncoding::kNone : encoding.color;
  switch (color) {
    case ColorEncoding::kNone:
      dds::setString(out.color_encoding, "");
      dds::setSequence(out.color, static_cast<const uint8_t*>(nullptr), 0);
      break;
    case ColorEncoding::kRaw:
      dds::setString(out.color_encoding, "rgb8");
      setPixels(out.color, frame.color);
      break;
    case ColorEncoding::kJpeg:
    case ColorEncoding::kPng: {
      cv::Mat bgr;
      cv::cvtColor(frame.color, bgr, cv::COLOR_RGB2BGR);  // imencode expects OpenCV's BGR order
      const bool jpeg = color == ColorEncoding::kJpeg;
      std::vector<uchar> bytes;
      const std::vector<int> params =
          jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, encoding.jpeg_quality}
               : std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 1};
      if (!cv::imencode(jpeg ? ".jpg" : ".png", bgr, bytes, params)) {
        return makeError("colour encoding failed");
      }
      dds::setString(out.color_encoding, jpeg ? "jpeg" : "png");
      setBytes(out.color, bytes);
      break;
    }
  }

  out.has_pose = frame.camera_to_world.has_value();
  if (out.has_pose) poseToArray(*frame.camera_to_world, out.camera_to_world);
  else std::fill(std::begin(out.camera_to_world), std::end(out.camera_to_world), 0.0);
  return Status::Ok();
}

Result<Frame> decodeFrame(const semfuse_msg_dds__Frame_& msg) {
  const int rows = static_cast<int>(msg.intrinsics.height);
  const int cols = static_cast<int>(msg.intrinsics.width);
  // Bounded so that a corrupt header cannot make us allocate gigabytes.
  if (rows <= 0 || cols <= 0 || rows > 8192 || cols > 8192) {
    return makeError("frame size " + std::to_string(cols) + "x" + std::to_string(rows) + " out of range");
  }
  Frame frame;
  frame.camera_id = str(msg.camera_id);
  frame.seq = msg.seq;
  frame.stamp = {msg.header.stamp.sec, msg.header.stamp.nanosec};
  frame.frame_id = str(msg.header.frame_id);
  frame.intrinsics = {cols, rows, msg.intrinsics.fx, msg.intrinsics.fy, msg.intrinsics.cx,
                      msg.intrinsics.cy};
  auto depth = decodeDepth(msg, rows, cols);
  if (!depth) return makeError("frame " + std::to_string(msg.seq) + ": " + depth.error());
  frame.depth = std::move(depth).value();
  auto color = decodeColor(msg, rows, cols);
  if (!color) return makeError("frame " + std::to_string(msg.seq) + ": " + color.error());
  frame.color = std::move(color).value();
  if (msg.has_pose) frame.camera_to_world = poseFromArray(msg.camera_to_world);
  return frame;
}

Status encodeSegmentation(const Segmentation& segmentation, semfuse_msg_dds__Segmentation_& out) {
  const cv::Mat& labels = segmentation.labels;
  if (labels.empty() || labels.type() != CV_16UC1) return makeError("labels must be a non-empty CV_16UC1 image");
  const cv::Mat& confidence = segmentation.confidence;
  if (!confidence.empty() && (confidence.type() != CV_32FC1 || confidence.size() != labels.size())) {
    return makeError("confidence must be CV_32FC1 of the label image's size");
  }
  out.header.stamp.sec = segmentation.stamp.sec;
  out.header.stamp.nanosec = segmentation.stamp.nanosec;
  dds::setString(out.camera_id, segmentation.camera_id);
  out.frame_seq = segmentation.frame_seq;
  dds::setString(out.segmenter_id, segmentation.segmenter_id);
  out.width = static_cast<uint32_t>(labels.cols);
  out.height = static_cast<uint32_t>(labels.rows);
  const cv::Mat continuous = labels.isContinuous() ? labels : labels.clone();
  dds::setSequence(out.labels, continuous.ptr<uint16_t>(), continuous.total());
  if (confidence.empty()) {
    dds::setString(out.confidence_encoding, "");
    dds::setSequence(out.confidence, static_cast<const uint8_t*>(nullptr), 0);
  } else {
    // 8 bits are plenty for a score that is summed over many frames, and a quarter of the bytes.
    cv::Mat bytes;
    confidence.convertTo(bytes, CV_8UC1, 255.0);
    dds::setString(out.confidence_encoding, "8UC1");
    setPixels(out.confidence, bytes);
  }
  return Status::Ok();
}

Result<cv::Mat> decodeImage(const sensor_msgs_msg_dds__Image_& image) {
  if (image.width == 0 || image.height == 0) return cv::Mat();
  const std::string encoding = str(image.encoding);
  int type = -1;
  if (encoding == "32FC1") type = CV_32FC1;
  else if (encoding == "32FC3") type = CV_32FC3;
  else if (encoding == "16UC1" || encoding == "mono16") type = CV_16UC1;
  else if (encoding == "8UC1" || encoding == "mono8") type = CV_8UC1;
  else if (encoding == "rgb8" || encoding == "bgr8" || encoding == "8UC3") type = CV_8UC3;
  else return makeError("unsupported image encoding '" + encoding + "'");
  if (image.is_bigendian && CV_ELEM_SIZE1(type) > 1) return makeError("big-endian images are not supported");
  const int rows = static_cast<int>(image.height);
  const int cols = static_cast<int>(image.width);
  const std::size_t row_bytes = static_cast<std::size_t>(cols) * CV_ELEM_SIZE(type);
  const std::size_t step = image.step == 0 ? row_bytes : image.step;
  if (step < row_bytes || image.data._length < step * (rows - 1) + row_bytes) {
    return makeError("image data shorter than its " + std::to_string(cols) + "x" + std::to_string(rows) + " size");
  }
  cv::Mat mat(rows, cols, type);
  for (int r = 0; r < rows; ++r) std::memcpy(mat.ptr(r), image.data._buffer + r * step, row_bytes);
  if (encoding == "bgr8") cv::cvtColor(mat, mat, cv::COLOR_BGR2RGB);
  return mat;
}

LabelLegend decodeLegend(const semfuse_msg_dds__LabelLegend_& msg) {
  LabelLegend legend;
  legend.name = str(msg.name);
  for (uint32_t i = 0; i < msg.labels._length; ++i) {
    const auto& e = msg.labels._buffer[i];
    legend.labels.push_back({e.id, str(e.name), {e.r, e.g, e.b}});
  }
  for (uint32_t i = 0; i < msg.background_ids._length; ++i) {
    legend.background_ids.push_back(msg.background_ids._buffer[i]);
  }
  return legend;
}

namespace {
std::vector<ReasonCount> counters(const dds_sequence_semfuse_msg_dds__Counter_& seq) {
  std::vector<ReasonCount> out;
  for (uint32_t i = 0; i < seq._length; ++i) {
    out.push_back({str(seq._buffer[i].reason), str(seq._buffer[i].camera_id), seq._buffer[i].count});
  }
  return out;
}
}  // namespace

ServerStatus decodeStatus(const semfuse_msg_dds__ServerStatus_& msg) {
  ServerStatus s;
  s.server_id = str(msg.server_id);
  s.version = str(msg.version);
  s.uptime_s = msg.uptime_s;
  s.frames_received = msg.frames_received;
  s.frames_integrated = msg.frames_integrated;
  s.frames_lost = msg.frames_lost;
  s.segmentations_received = msg.segmentations_received;
  s.segmentations_integrated = msg.segmentations_integrated;
  s.dropped = counters(msg.dropped);
  s.rejected = counters(msg.rejected);
  s.queued_frames = msg.queued_frames;
  s.pending_segmentations = msg.pending_segmentations;
  s.history_frames = msg.history_frames;
  s.voxel_size = msg.voxel_size;
  s.truncation = msg.truncation;
  s.allocated_voxels = msg.allocated_voxels;
  s.allocated_blocks = msg.allocated_blocks;
  s.map_bytes = msg.map_bytes;
  s.rss_bytes = msg.rss_bytes;
  for (uint32_t i = 0; i < msg.cameras._length; ++i) {
    const auto& c = msg.cameras._buffer[i];
    s.cameras.push_back({str(c.camera_id), c.tracking_state, c.last_seq, c.frames_received,
                         c.frames_integrated, c.frames_lost, c.frame_rate_hz, c.last_frame_age_s, c.stale});
  }
  for (uint32_t i = 0; i < msg.last_errors._length; ++i) {
    const auto& e = msg.last_errors._buffer[i];
    s.last_errors.push_back({e.stamp.sec + e.stamp.nanosec * 1e-9, str(e.source), str(e.message)});
  }
  s.map_file = str(msg.map_file);
  s.last_save_ok = msg.last_save_ok;
  s.last_save_age_s = msg.last_save_age_s;
  return s;
}

}  // namespace semfuse::client::wire
