#include "semfuse/wire/message_codecs.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/core.hpp>

#include "semfuse/core/camera_check.hpp"
#include "semfuse/core/legend_io.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::wire {

namespace {
// A CV_16UC1 image's pixels, row-major, as a message sequence takes them.
std::vector<uint16_t> uint16Pixels(const cv::Mat& image) {
  const cv::Mat continuous = image.isContinuous() ? image : image.clone();
  return {continuous.ptr<uint16_t>(), continuous.ptr<uint16_t>() + continuous.total()};
}
}  // namespace

const std::vector<std::string>& confidenceEncodings() {
  static const std::vector<std::string> names = {"", "8UC1", "32FC1"};
  return names;
}

Result<EncodedSegmentation> encodeSegmentation(const Segmentation& segmentation,
                                               const std::string& confidence_encoding) {
  const cv::Mat& labels = segmentation.labels;
  if (labels.type() != CV_16UC1)
    return makeError("encodeSegmentation: labels must be CV_16UC1, got " + typeName(labels.type()));
  if (Status s = validateImageSize("segmentation", labels.cols, labels.rows); !s) return makeError(s.error());
  const bool has_confidence = !segmentation.confidence.empty();
  const std::string encoding = has_confidence ? confidence_encoding : "";
  if (Status s = validateEncoding("confidence", encoding, confidenceEncodings()); !s) return makeError(s.error());
  if (has_confidence) {
    if (segmentation.confidence.size() != labels.size()) {
      return makeError("encodeSegmentation: confidence size differs from the labels'");
    }
    if (Status s = validateConfidence(segmentation.confidence); !s) return makeError(s.error());
  }
  const cv::Mat& instances = segmentation.instances;
  if (!instances.empty() && (instances.type() != CV_16UC1 || instances.size() != labels.size()))
    return makeError("encodeSegmentation: instances must be CV_16UC1 of the labels' size, got " +
                     typeName(instances.type()) + " " + std::to_string(instances.cols) + "x" +
                     std::to_string(instances.rows));

  EncodedSegmentation encoded;
  auto& msg = encoded.msg();
  msg.header.stamp.sec = segmentation.stamp.sec;
  msg.header.stamp.nanosec = segmentation.stamp.nanosec;
  msg.header.frame_id = encoded.keepString("");
  msg.camera_id = encoded.keepString(segmentation.camera_id);
  msg.frame_seq = segmentation.frame_seq;
  msg.segmenter_id = encoded.keepString(segmentation.segmenter_id);
  msg.width = static_cast<uint32_t>(labels.cols);
  msg.height = static_cast<uint32_t>(labels.rows);
  encoded.keepSequence(msg.labels, uint16Pixels(labels));
  msg.confidence_encoding = encoded.keepString(encoding);
  std::vector<uint8_t> confidence;
  if (encoding == "8UC1") {
    cv::Mat bytes;
    segmentation.confidence.convertTo(bytes, CV_8U, 255.0);  // rounds and saturates
    confidence.assign(bytes.ptr<uint8_t>(), bytes.ptr<uint8_t>() + bytes.total());
  } else if (encoding == "32FC1") {
    const cv::Mat floats =
        segmentation.confidence.isContinuous() ? segmentation.confidence : segmentation.confidence.clone();
    confidence.assign(floats.ptr<uint8_t>(), floats.ptr<uint8_t>() + floats.total() * sizeof(float));
  }
  encoded.keepSequence(msg.confidence, std::move(confidence));
  encoded.keepSequence(msg.instances, instances.empty() ? std::vector<uint16_t>{} : uint16Pixels(instances));
  return encoded;
}

namespace {
// The optional instance map, into segmentation.instances (its labels already decoded).
Status decodeInstances(const semfuse_msg_dds__Segmentation_& msg, Segmentation& segmentation) {
  if (Status s = validateSequence("instances", msg.instances._length, msg.instances._maximum, msg.instances._buffer);
      !s)
    return s;
  if (msg.instances._length == 0) return Status::Ok();  // a class-only segmenter
  const uint64_t pixels = static_cast<uint64_t>(msg.width) * msg.height;
  if (msg.instances._length != pixels)
    return makeError("instances: " + std::to_string(msg.instances._length) + " ids for " + std::to_string(msg.width) +
                     "x" + std::to_string(msg.height) + " labels, expected " + std::to_string(pixels) + " (or none)");
  const cv::Mat ids(segmentation.labels.size(), CV_16UC1, msg.instances._buffer);
  // An instance is a part of a class: ids on pixels that all lack a label say nothing the map can use.
  const cv::Mat named = ids != 0;
  const int named_pixels = cv::countNonZero(named);
  if (named_pixels > 0 && cv::countNonZero(named & (segmentation.labels != 0)) == 0)
    return makeError("instances: " + std::to_string(named_pixels) +
                     " pixels name an instance but none has a label (0 = unlabeled): send each instance's class in "
                     "labels");
  segmentation.instances = ids.clone();
  return Status::Ok();
}
}  // namespace

Result<Segmentation> decodeSegmentation(const semfuse_msg_dds__Segmentation_& msg) {
  Segmentation segmentation;
  segmentation.camera_id = stringOf(msg.camera_id);
  if (segmentation.camera_id.empty()) return makeError("segmentation: empty camera_id");
  segmentation.frame_seq = msg.frame_seq;
  segmentation.segmenter_id = stringOf(msg.segmenter_id);
  segmentation.stamp = {msg.header.stamp.sec, msg.header.stamp.nanosec};
  if (Status s = validateImageSize("segmentation", msg.width, msg.height); !s) return makeError(s.error());
  const int w = static_cast<int>(msg.width), h = static_cast<int>(msg.height);

  if (Status s = validateSequence("labels", msg.labels._length, msg.labels._maximum, msg.labels._buffer); !s) {
    return makeError(s.error());
  }
  if (msg.labels._length != static_cast<uint64_t>(msg.width) * msg.height) {
    return makeError("labels: " + std::to_string(msg.labels._length) + " labels for " + std::to_string(w) + "x" +
                     std::to_string(h) + ", expected " + std::to_string(static_cast<uint64_t>(w) * h));
  }
  segmentation.labels.create(h, w, CV_16UC1);
  std::memcpy(segmentation.labels.data, msg.labels._buffer, msg.labels._length * sizeof(uint16_t));

  const std::string encoding = stringOf(msg.confidence_encoding);
  if (Status s = validateEncoding("confidence", encoding, confidenceEncodings()); !s) return makeError(s.error());
  if (Status s =
          validateSequence("confidence", msg.confidence._length, msg.confidence._maximum, msg.confidence._buffer);
      !s) {
    return makeError(s.error());
  }
  const std::size_t bytes = msg.confidence._length;
  if (encoding.empty()) {
    if (bytes != 0) return makeError("confidence: " + std::to_string(bytes) + " bytes with encoding \"\" (none)");
    segmentation.confidence = cv::Mat(h, w, CV_32FC1, cv::Scalar(1.0f));
  } else if (encoding == "8UC1") {
    if (Status s = validateDataSize("confidence", bytes, msg.width, msg.height, encoding, 1); !s)
      return makeError(s.error());
    const cv::Mat bytes_view(h, w, CV_8UC1, msg.confidence._buffer);
    bytes_view.convertTo(segmentation.confidence, CV_32F, 1.0 / 255.0);
  } else {
    if (Status s = validateDataSize("confidence", bytes, msg.width, msg.height, encoding, 4); !s)
      return makeError(s.error());
    segmentation.confidence.create(h, w, CV_32FC1);
    std::memcpy(segmentation.confidence.data, msg.confidence._buffer, bytes);
    if (Status s = validateConfidence(segmentation.confidence); !s) return makeError(s.error());
  }
  if (Status s = decodeInstances(msg, segmentation); !s) return makeError(s.error());
  return segmentation;
}

EncodedTrackedPose encodeTrackedPose(const TrackedPose& pose) {
  EncodedTrackedPose encoded;
  auto& msg = encoded.msg();
  msg.header.stamp.sec = pose.stamp.sec;
  msg.header.stamp.nanosec = pose.stamp.nanosec;
  msg.header.frame_id = encoded.keepString(pose.frame_id);
  msg.camera_id = encoded.keepString(pose.camera_id);
  msg.seq = pose.seq;
  msg.state = static_cast<uint8_t>(pose.state);
  msg.posed = pose.posed;
  poseToRowMajor(pose.camera_to_world, msg.camera_to_world);
  msg.inlier_ratio = pose.inlier_ratio;
  msg.residual = pose.residual;
  msg.iterations = pose.iterations;
  msg.track_ms = pose.track_ms;
  return encoded;
}

Result<TrackedPose> decodeTrackedPose(const semfuse_msg_dds__TrackedPose_& msg) {
  if (msg.state > static_cast<uint8_t>(PoseState::kLost)) {
    return makeError("tracked pose: unknown state " + std::to_string(msg.state) +
                     " (known: 0 given, 1 tracked, 2 refined, 3 lost)");
  }
  TrackedPose pose;
  pose.camera_id = stringOf(msg.camera_id);
  pose.seq = msg.seq;
  pose.stamp = {msg.header.stamp.sec, msg.header.stamp.nanosec};
  pose.frame_id = stringOf(msg.header.frame_id);
  pose.state = static_cast<PoseState>(msg.state);
  pose.posed = msg.posed;
  pose.camera_to_world = poseFromRowMajor(msg.camera_to_world);
  // A lost frame may carry any placeholder; a used pose must be a rigid transform.
  if (pose.state != PoseState::kLost) {
    if (Status s = checkRigidPose(pose.camera_to_world); !s) return s.errorInfo().prefixed("tracked ");
  }
  pose.inlier_ratio = msg.inlier_ratio;
  pose.residual = msg.residual;
  pose.iterations = msg.iterations;
  pose.track_ms = msg.track_ms;
  return pose;
}

EncodedLegend encodeLegend(const LabelLegend& legend, Stamp stamp) {
  EncodedLegend encoded;
  auto& msg = encoded.msg();
  msg.header.stamp.sec = stamp.sec;
  msg.header.stamp.nanosec = stamp.nanosec;
  msg.header.frame_id = encoded.keepString("");
  msg.name = encoded.keepString(legend.name);
  std::vector<semfuse_msg_dds__LabelEntry_> entries;
  entries.reserve(legend.labels.size());
  for (const LabelInfo& label : legend.labels) {
    entries.push_back({label.id, encoded.keepString(label.name), label.rgb[0], label.rgb[1], label.rgb[2]});
  }
  encoded.keepSequence(msg.labels, std::move(entries));
  encoded.keepSequence(msg.background_ids, legend.background_ids);
  return encoded;
}

Result<LabelLegend> decodeLegend(const semfuse_msg_dds__LabelLegend_& msg) {
  if (Status s = validateSequence("legend labels", msg.labels._length, msg.labels._maximum, msg.labels._buffer); !s) {
    return makeError(s.error());
  }
  if (Status s = validateSequence("legend background_ids", msg.background_ids._length, msg.background_ids._maximum,
                                  msg.background_ids._buffer);
      !s) {
    return makeError(s.error());
  }
  LabelLegend legend;
  legend.name = stringOf(msg.name);
  for (uint32_t i = 0; i < msg.labels._length; ++i) {
    const auto& entry = msg.labels._buffer[i];
    legend.labels.push_back({entry.id, stringOf(entry.name), {entry.r, entry.g, entry.b}});
  }
  std::stable_sort(legend.labels.begin(), legend.labels.end(),
                   [](const LabelInfo& a, const LabelInfo& b) { return a.id < b.id; });
  legend.background_ids.assign(msg.background_ids._buffer, msg.background_ids._buffer + msg.background_ids._length);
  std::sort(legend.background_ids.begin(), legend.background_ids.end());
  if (Status s = validateLegend(legend); !s) return makeError(s.error());
  return legend;
}

EncodedObjectEvents encodeObjectEvents(const ObjectEvents& events) {
  EncodedObjectEvents encoded;
  auto& msg = encoded.msg();
  msg.header.stamp.sec = events.stamp.sec;
  msg.header.stamp.nanosec = events.stamp.nanosec;
  msg.header.frame_id = encoded.keepString("");
  msg.update = events.update;
  msg.object_count = events.object_count;
  std::vector<semfuse_msg_dds__ObjectEvent_> entries(events.events.size());
  for (std::size_t i = 0; i < events.events.size(); ++i) {
    const ObjectEvent& event = events.events[i];
    entries[i].kind = static_cast<uint8_t>(event.kind);
    entries[i].id = event.id;
    entries[i].label = event.label;
    encoded.keepSequence(entries[i].others, event.others);
  }
  encoded.keepSequence(msg.events, std::move(entries));
  return encoded;
}

Result<ObjectEvents> decodeObjectEvents(const semfuse_msg_dds__ObjectEvents_& msg) {
  if (Status s = validateSequence("object events", msg.events._length, msg.events._maximum, msg.events._buffer); !s)
    return makeError(s.error());
  ObjectEvents events;
  events.update = msg.update;
  events.stamp = {msg.header.stamp.sec, msg.header.stamp.nanosec};
  events.object_count = msg.object_count;
  events.events.reserve(msg.events._length);
  for (uint32_t i = 0; i < msg.events._length; ++i) {
    const semfuse_msg_dds__ObjectEvent_& entry = msg.events._buffer[i];
    if (entry.kind > static_cast<uint8_t>(ObjectEventKind::kVanished)) {
      return makeError("object events: event " + std::to_string(i) + " has unknown kind " + std::to_string(entry.kind) +
                       " (known: 0 appeared, 1 merged, 2 split, 3 vanished)");
    }
    if (Status s =
            validateSequence("object event others", entry.others._length, entry.others._maximum, entry.others._buffer);
        !s)
      return makeError(s.error());
    ObjectEvent event;
    event.kind = static_cast<ObjectEventKind>(entry.kind);
    event.id = entry.id;
    event.label = entry.label;
    event.others.assign(entry.others._buffer, entry.others._buffer + entry.others._length);
    events.events.push_back(std::move(event));
  }
  return events;
}

}  // namespace semfuse::wire
