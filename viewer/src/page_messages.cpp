#include "page_messages.hpp"

#include <cstring>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

namespace semfuse::viewer {
namespace {

template <class T>
void append(std::string& out, const T* data, std::size_t count) {
  const std::size_t at = out.size();
  out.resize(at + count * sizeof(T));
  if (count > 0) std::memcpy(out.data() + at, data, count * sizeof(T));
}

template <class T>
void appendValue(std::string& out, T value) {
  append(out, &value, 1);
}

void padTo4(std::string& out) { out.resize((out.size() + 3) / 4 * 4, '\0'); }

void appendOrigin(std::string& out, const BlockOrigin& origin) { append(out, origin.data(), 3); }

std::string number(double value) { return std::isfinite(value) ? fmt::format("{:.6g}", value) : "null"; }

}  // namespace

std::string blockMessage(const MeshBlock& block, double voxel_size) {
  const std::size_t vertices = block.vertexCount();
  const std::size_t triangles = block.triangleCount();
  std::string out;
  out.reserve(28 + vertices * 23 + triangles * 12 + 4);
  appendValue(out, static_cast<uint32_t>(BlockMessage::kBlock));
  appendOrigin(out, block.origin);
  appendValue(out, static_cast<uint32_t>(vertices));
  appendValue(out, static_cast<uint32_t>(triangles));
  appendValue(out, block.own_vertices);
  std::vector<float> positions(3 * vertices);
  for (std::size_t i = 0; i < vertices; ++i) {
    const Eigen::Vector3f p = block.position(i, voxel_size);
    for (int axis = 0; axis < 3; ++axis) positions[3 * i + axis] = p[axis];
  }
  append(out, positions.data(), positions.size());
  std::vector<float> scores(block.scores);
  scores.resize(vertices, 0.0F);
  append(out, scores.data(), scores.size());
  const std::vector<uint32_t> indices(block.triangles.begin(), block.triangles.end());
  append(out, indices.data(), indices.size());
  append(out, block.labels.data(), block.labels.size());
  padTo4(out);
  if (block.colors.size() == 3 * vertices) {
    append(out, block.colors.data(), block.colors.size());
  } else {
    out.resize(out.size() + 3 * vertices, '\0');
  }
  return out;
}

std::string removedMessage(const BlockOrigin& origin) {
  std::string out;
  appendValue(out, static_cast<uint32_t>(BlockMessage::kRemoved));
  appendOrigin(out, origin);
  return out;
}

std::string clearedMessage() {
  std::string out;
  appendValue(out, static_cast<uint32_t>(BlockMessage::kCleared));
  return out;
}

std::string raycastMessage(const RaycastImages& view, const LabelLegend& legend) {
  cv::Mat bgr(view.labels.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  for (int v = 0; v < view.labels.rows; ++v)
    for (int u = 0; u < view.labels.cols; ++u) {
      if (!view.depth.empty() && !(view.depth.at<float>(v, u) > 0.0F)) continue;
      const auto rgb = legend.colorOf(view.labels.at<uint16_t>(v, u));
      bgr.at<cv::Vec3b>(v, u) = {rgb[2], rgb[1], rgb[0]};
    }
  std::vector<uint8_t> png;
  cv::imencode(".png", bgr, png);
  std::string out;
  appendValue(out, static_cast<uint32_t>(BlockMessage::kRaycast));
  append(out, png.data(), png.size());
  return out;
}

std::string legendJson(const LabelLegend& legend) {
  std::string labels;
  for (const LabelInfo& label : legend.labels) {
    if (!labels.empty()) labels += ",";
    labels += fmt::format(R"({{"id":{},"name":{},"rgb":[{},{},{}],"background":{}}})", label.id, jsonString(label.name),
                          label.rgb[0], label.rgb[1], label.rgb[2], legend.isBackground(label.id) ? "true" : "false");
  }
  return fmt::format(R"({{"type":"legend","name":{},"labels":[{}]}})", jsonString(legend.name), labels);
}

std::string statusJson(const std::optional<ServerStatus>& status, const FollowerCounters& follower) {
  std::string server = "null";
  if (status) {
    std::string cameras;
    for (const CameraStatus& camera : status->cameras) {
      if (!cameras.empty()) cameras += ",";
      cameras += fmt::format(R"({{"id":{},"integrated":{},"state":{}}})", jsonString(camera.camera_id),
                             camera.frames_integrated, jsonString(trackingStateName(camera.tracking_state)));
    }
    uint64_t dropped = 0, rejected = 0;
    for (const ReasonCount& r : status->dropped) dropped += r.count;
    for (const ReasonCount& r : status->rejected) rejected += r.count;
    server = fmt::format(
        R"({{"id":{},"uptime_s":{},"frames_received":{},"frames_integrated":{},"frames_lost":{},"dropped":{},"rejected":{},"queued_frames":{},"allocated_blocks":{},"map_bytes":{},"rss_bytes":{},"voxel_size":{},"cameras":[{}]}})",
        jsonString(status->server_id), number(status->uptime_s), status->frames_received, status->frames_integrated,
        status->frames_lost, dropped, rejected, status->queued_frames, status->allocated_blocks, status->map_bytes,
        status->rss_bytes, number(status->voxel_size), cameras);
  }
  return fmt::format(
      R"({{"type":"status","server":{},"viewer":{{"blocks":{},"vertices":{},"revision":{},"updates":{},"catch_ups":{},"gaps":{},"browsers":{}}}}})",
      server, follower.blocks, follower.vertices, follower.revision, follower.updates, follower.catch_ups,
      follower.gaps, follower.browsers);
}

std::string posesJson(const std::vector<TrackedPose>& poses) {
  std::string items;
  for (const TrackedPose& pose : poses) {
    if (!items.empty()) items += ",";
    std::string matrix;
    const Eigen::Matrix4d m = pose.camera_to_world.matrix();
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) matrix += (matrix.empty() ? "" : ",") + number(m(row, col));
    items += fmt::format(R"({{"camera":{},"seq":{},"posed":{},"state":{},"m":[{}]}})", jsonString(pose.camera_id),
                         pose.seq, pose.posed ? "true" : "false",
                         jsonString(trackingStateName(static_cast<uint8_t>(pose.state))), matrix);
  }
  return R"({"type":"poses","poses":[)" + items + "]}";
}

std::string labelsAtJson(const Eigen::Vector3d& point, const VoxelSample& sample, const LabelLegend& legend,
                         const ObjectInstance* object) {
  const LabelInfo* info = legend.find(sample.label);
  std::string instance = "null";
  if (object) {
    const Eigen::Vector3d size = object->bbox_max - object->bbox_min;
    instance = fmt::format(R"({{"id":{},"voxels":{},"size":[{},{},{}],"centroid":[{},{},{}]}})", object->id,
                           object->voxel_count, number(size.x()), number(size.y()), number(size.z()),
                           number(object->centroid.x()), number(object->centroid.y()), number(object->centroid.z()));
  }
  return fmt::format(
      R"({{"type":"labels_at","point":[{},{},{}],"observed":{},"label":{},"name":{},"confidence":{},"tsdf":{},"weight":{},"object":{}}})",
      number(point.x()), number(point.y()), number(point.z()), sample.observed ? "true" : "false", sample.label,
      jsonString(info ? info->name : "label " + std::to_string(sample.label)), number(sample.confidence),
      number(sample.tsdf), number(sample.weight), instance);
}

std::string errorJson(const std::string& what, const std::string& message) {
  return fmt::format(R"({{"type":"error","what":{},"message":{}}})", jsonString(what), jsonString(message));
}

}  // namespace semfuse::viewer
