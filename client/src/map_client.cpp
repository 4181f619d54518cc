#include "semfuse/client/map_client.hpp"

#include <atomic>
#include <mutex>
#include <string>
#include <type_traits>
#include <utility>

#include "mesh_assembly.hpp"
#include "rpc_call.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/rpc.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/reply_status.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "semfuse/wire/status_codec.hpp"

namespace semfuse::client {
namespace {}  // namespace

// The object events reader, made on the first takeObjectEvents(): a client that never asks
// subscribes to nothing more (and needs no DDS Security permission for the topic).
struct ObjectEventsReader {
  explicit ObjectEventsReader(const dds::Participant& p)
      : topic(p, dds::topics::kObjectEvents),
        reader(topic, dds::qos::objectEvents()),
        ready(reader.handle()),
        waitset(p) {
    waitset.attach(ready.handle());
  }
  dds::Topic<semfuse_msg_dds__ObjectEvents_> topic;
  dds::Reader<semfuse_msg_dds__ObjectEvents_> reader;
  dds::ReadCondition ready;
  dds::WaitSet waitset;
};

struct MapClient::Impl {
  explicit Impl(const dds::Participant& p)
      : participant(p),
        raycast(p, dds::topics::raycast()),
        labels_at(p, dds::topics::labelsAt()),
        region(p, dds::topics::region()),
        objects(p, dds::topics::objects()),
        mesh(p, dds::topics::mesh()),
        admin(p, dds::topics::admin()),
        status_topic(p, dds::topics::kStatus),
        legend_topic(p, dds::topics::kLabels),
        status_reader(status_topic, dds::qos::status()),
        legend_reader(legend_topic, dds::qos::legend()),
        status_ready(status_reader.handle()),
        legend_ready(legend_reader.handle()),
        status_waitset(p),
        legend_waitset(p),
        pose_topic(p, dds::topics::kPoses),
        pose_reader(pose_topic, dds::qos::poseRecording()),
        pose_ready(pose_reader.handle()),
        pose_waitset(p) {
    status_waitset.attach(status_ready.handle());
    legend_waitset.attach(legend_ready.handle());
    pose_waitset.attach(pose_ready.handle());
  }

  std::vector<TrackedPose> takePoses() {
    std::vector<TrackedPose> out;
    while (auto sample = pose_reader.take()) {
      if (auto decoded = wire::decodeTrackedPose(**sample)) out.push_back(std::move(decoded).value());
      else ++rejected_poses;
    }
    return out;
  }

  ObjectEventsReader& objectEventsReader() {
    std::lock_guard lock(object_events_mutex);
    if (!object_events) object_events = std::make_unique<ObjectEventsReader>(participant);
    return *object_events;
  }

  std::vector<ObjectEvents> takeObjectEvents(ObjectEventsReader& events) {
    std::vector<ObjectEvents> out;
    while (auto sample = events.reader.take()) {
      if (auto decoded = wire::decodeObjectEvents(**sample)) out.push_back(std::move(decoded).value());
      else ++rejected_object_events;
    }
    return out;
  }

  void poll() {
    std::lock_guard lock(mutex);
    while (auto s = status_reader.take()) {
      if (auto decoded = wire::decodeServerStatus(**s)) status = std::move(decoded).value();
    }
    while (auto l = legend_reader.take()) {
      // A legend the server should never have sent is kept out rather than half-used.
      if (auto decoded = wire::decodeLegend(**l)) legend = std::move(decoded).value();
    }
  }

  const dds::Participant& participant;
  Rpc<wire::RaycastCodec> raycast;
  Rpc<wire::LabelsAtCodec> labels_at;
  Rpc<wire::RegionCodec> region;
  Rpc<wire::ObjectsCodec> objects;
  Rpc<wire::MeshCodec> mesh;
  Rpc<wire::AdminCodec> admin;
  dds::Topic<semfuse_msg_dds__ServerStatus_> status_topic;
  dds::Topic<semfuse_msg_dds__LabelLegend_> legend_topic;
  dds::Reader<semfuse_msg_dds__ServerStatus_> status_reader;
  dds::Reader<semfuse_msg_dds__LabelLegend_> legend_reader;
  dds::ReadCondition status_ready;
  dds::ReadCondition legend_ready;
  dds::WaitSet status_waitset;
  dds::WaitSet legend_waitset;
  std::mutex mutex;
  std::optional<ServerStatus> status;
  std::optional<LabelLegend> legend;
  dds::Topic<semfuse_msg_dds__TrackedPose_> pose_topic;
  dds::Reader<semfuse_msg_dds__TrackedPose_> pose_reader;
  dds::ReadCondition pose_ready;
  dds::WaitSet pose_waitset;
  std::atomic<uint64_t> rejected_poses{0};
  std::mutex object_events_mutex;
  std::unique_ptr<ObjectEventsReader> object_events;
  std::atomic<uint64_t> rejected_object_events{0};
};

MapClient::MapClient(const dds::Participant& participant)
    : impl_(std::make_unique<Impl>(participant)), distance_(makeDistanceRpcs(participant)) {}
MapClient::~MapClient() = default;

CallResult<RaycastImages> MapClient::raycast(const Pose& camera_to_world, const PinholeIntrinsics& intrinsics,
                                             RaycastLayers layers, Timeout timeout, float max_range) {
  return call<wire::RaycastCodec>(impl_->raycast, {camera_to_world, intrinsics, layers, max_range}, timeout);
}

CallResult<std::vector<VoxelSample>> MapClient::labelsAt(const std::vector<Eigen::Vector3d>& points, Timeout timeout) {
  return call<wire::LabelsAtCodec>(impl_->labels_at, {points}, timeout);
}

CallResult<RegionSummary> MapClient::region(const Box& box, Timeout timeout) {
  return call<wire::RegionCodec>(impl_->region, box, timeout);
}

CallResult<std::vector<ObjectInstance>> MapClient::objects(LabelId label, uint32_t min_voxels, Timeout timeout) {
  ObjectsRequest request;
  request.label = label;
  request.min_voxels = min_voxels;
  return objects(request, timeout);
}

CallResult<std::vector<ObjectInstance>> MapClient::objects(const ObjectsRequest& request, Timeout timeout) {
  return call<wire::ObjectsCodec>(impl_->objects, request, timeout);
}

CallResult<MeshData> MapClient::mesh(const std::optional<Box>& box, Timeout timeout, uint32_t object_id) {
  detail::MeshAssembly assembly;
  for (uint32_t chunk = 0; chunk < assembly.chunkCount(); ++chunk) {
    auto reply = call<wire::MeshCodec>(impl_->mesh, {box, assembly.meshId(), chunk, object_id}, timeout);
    if (!reply) return {reply.failure(), makeError(reply.errorCode(), reply.error())};
    if (Status added = assembly.add(std::move(reply).value(), chunk); !added) return {Failure::kClient, added.error()};
  }
  auto mesh = std::move(assembly).finish();
  if (!mesh) return {Failure::kClient, mesh.error()};
  return std::move(mesh).value();
}

CallResult<ServerStatus> MapClient::stats(Timeout timeout) {
  return call<wire::AdminCodec>(impl_->admin, {AdminCommand::kStats, ""}, timeout);
}
CallResult<ServerStatus> MapClient::save(const std::string& path, Timeout timeout) {
  return call<wire::AdminCodec>(impl_->admin, {AdminCommand::kSave, path}, timeout);
}
CallResult<ServerStatus> MapClient::load(const std::string& path, Timeout timeout) {
  return call<wire::AdminCodec>(impl_->admin, {AdminCommand::kLoad, path}, timeout);
}
CallResult<ServerStatus> MapClient::reset(Timeout timeout) {
  return call<wire::AdminCodec>(impl_->admin, {AdminCommand::kReset, ""}, timeout);
}

std::optional<ServerStatus> MapClient::latestStatus() {
  impl_->poll();
  std::lock_guard lock(impl_->mutex);
  return impl_->status;
}

std::optional<LabelLegend> MapClient::latestLegend() {
  impl_->poll();
  std::lock_guard lock(impl_->mutex);
  return impl_->legend;
}

std::optional<ServerStatus> MapClient::waitForStatus(Timeout timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (auto s = latestStatus()) return s;
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    static_cast<void>(impl_->status_waitset.wait(DDS_MSECS(left.count())));
  }
}

std::optional<LabelLegend> MapClient::waitForLegend(Timeout timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (auto l = latestLegend()) return l;
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    static_cast<void>(impl_->legend_waitset.wait(DDS_MSECS(left.count())));
  }
}

std::vector<TrackedPose> MapClient::takePoses(Timeout timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    std::vector<TrackedPose> poses = impl_->takePoses();
    if (!poses.empty()) return poses;
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return poses;
    static_cast<void>(impl_->pose_waitset.wait(DDS_MSECS(left.count())));
  }
}

uint64_t MapClient::rejectedPoses() const { return impl_->rejected_poses.load(); }

std::vector<ObjectEvents> MapClient::takeObjectEvents(Timeout timeout) {
  ObjectEventsReader& reader = impl_->objectEventsReader();
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    std::vector<ObjectEvents> events = impl_->takeObjectEvents(reader);
    if (!events.empty()) return events;
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return events;
    static_cast<void>(reader.waitset.wait(DDS_MSECS(left.count())));
  }
}

uint64_t MapClient::rejectedObjectEvents() const { return impl_->rejected_object_events.load(); }

}  // namespace semfuse::client
