#include "semfuse/client/map_client.hpp"

#include <mutex>

#include "reply_decoding.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/rpc.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/reply_status.hpp"

namespace semfuse::client {
namespace {

using RaycastRpc = dds::RpcClient<semfuse_srv_dds__Raycast_Request_, semfuse_srv_dds__Raycast_Response_>;
using LabelsAtRpc = dds::RpcClient<semfuse_srv_dds__LabelsAt_Request_, semfuse_srv_dds__LabelsAt_Response_>;
using RegionRpc = dds::RpcClient<semfuse_srv_dds__Region_Request_, semfuse_srv_dds__Region_Response_>;
using ObjectsRpc = dds::RpcClient<semfuse_srv_dds__Objects_Request_, semfuse_srv_dds__Objects_Response_>;
using MeshRpc = dds::RpcClient<semfuse_srv_dds__Mesh_Request_, semfuse_srv_dds__Mesh_Response_>;
using AdminRpc = dds::RpcClient<semfuse_srv_dds__Admin_Request_, semfuse_srv_dds__Admin_Response_>;

geometry_msgs_msg_dds__Point_ toPoint(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

// A reply with a non-OK status: the server's message, with the code of its status.
template <class Reply>
Error serverError(const Reply& reply) {
  return makeError(wire::errorCodeOfReplyStatus(reply.status),
                   "server error " + std::to_string(reply.status) + ": " + std::string(dds::replyMessage(reply)));
}
Eigen::Vector3d fromPoint(const geometry_msgs_msg_dds__Point_& p) { return {p.x, p.y, p.z}; }

// One request/reply round trip. RpcClient reports only transport problems as errors (no server
// matched, no reply in time), which are timeouts from the caller's point of view; a reply with a
// non-OK status is the server's error.
template <class Reply, class Rpc, class Request, class Convert>
auto call(Rpc& rpc, dds::Sample<Request>& request, Timeout timeout, Convert&& convert)
    -> CallResult<decltype(convert(std::declval<const Reply&>()))> {
  auto reply = rpc.call(*request, timeout);
  if (!reply) return {Failure::kTimeout, reply.error()};
  const Reply& r = *reply.value();
  if (!dds::replyOk(r)) {
    return {Failure::kServer, serverError(r)};
  }
  return convert(r);
}

}  // namespace

struct MapClient::Impl {
  explicit Impl(const dds::Participant& p)
      : raycast(p, dds::topics::raycast()),
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
        legend_waitset(p) {
    status_waitset.attach(status_ready.handle());
    legend_waitset.attach(legend_ready.handle());
  }

  void poll() {
    std::lock_guard lock(mutex);
    while (auto s = status_reader.take()) status = detail::decodeStatus(**s);
    while (auto l = legend_reader.take()) {
      // A legend the server should never have sent is kept out rather than half-used.
      if (auto decoded = wire::decodeLegend(**l)) legend = std::move(decoded).value();
    }
  }

  CallResult<ServerStatus> adminCall(uint8_t command, const std::string& path, Timeout timeout) {
    dds::Sample<semfuse_srv_dds__Admin_Request_> request;
    request->command = command;
    dds::setString(request->path, path);
    return call<semfuse_srv_dds__Admin_Response_>(admin, request, timeout,
                                                  [](const auto& r) { return detail::decodeStatus(r.server_status); });
  }

  RaycastRpc raycast;
  LabelsAtRpc labels_at;
  RegionRpc region;
  ObjectsRpc objects;
  MeshRpc mesh;
  AdminRpc admin;
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
};

MapClient::MapClient(const dds::Participant& participant) : impl_(std::make_unique<Impl>(participant)) {}
MapClient::~MapClient() = default;

CallResult<RaycastImages> MapClient::raycast(const Pose& camera_to_world, const PinholeIntrinsics& intrinsics,
                                             uint32_t layers, Timeout timeout, float max_range) {
  dds::Sample<semfuse_srv_dds__Raycast_Request_> request;
  wire::poseToRowMajor(camera_to_world, request->camera_to_world);
  request->intrinsics = {static_cast<uint32_t>(intrinsics.width),
                         static_cast<uint32_t>(intrinsics.height),
                         intrinsics.fx,
                         intrinsics.fy,
                         intrinsics.cx,
                         intrinsics.cy};
  request->layers = layers;
  request->max_range = max_range;
  auto reply = impl_->raycast.call(*request, timeout);
  if (!reply) return {Failure::kTimeout, reply.error()};
  auto& r = *reply.value();
  if (!dds::replyOk(r)) {
    return {Failure::kServer, serverError(r)};
  }
  RaycastImages images;
  const std::pair<sensor_msgs_msg_dds__Image_*, cv::Mat*> layers_out[] = {{&r.depth, &images.depth},
                                                                          {&r.normals, &images.normals},
                                                                          {&r.labels, &images.labels},
                                                                          {&r.confidence, &images.confidence},
                                                                          {&r.color, &images.color}};
  for (const auto& [image, mat] : layers_out) {
    auto decoded = detail::takeImage(*image);
    if (!decoded) return {Failure::kClient, "raycast reply: " + decoded.error()};
    *mat = std::move(decoded).value();
  }
  return images;
}

CallResult<std::vector<VoxelSample>> MapClient::labelsAt(const std::vector<Eigen::Vector3d>& points, Timeout timeout) {
  dds::Sample<semfuse_srv_dds__LabelsAt_Request_> request;
  std::vector<geometry_msgs_msg_dds__Point_> wire_points;
  for (const auto& p : points) wire_points.push_back(toPoint(p));
  dds::setSequence(request->points, wire_points.data(), wire_points.size());
  return call<semfuse_srv_dds__LabelsAt_Response_>(impl_->labels_at, request, timeout, [](const auto& r) {
    std::vector<VoxelSample> samples;
    for (uint32_t i = 0; i < r.samples._length; ++i) {
      const auto& s = r.samples._buffer[i];
      samples.push_back({s.observed, s.label, s.confidence, s.tsdf, s.weight});
    }
    return samples;
  });
}

CallResult<RegionSummary> MapClient::region(const Box& box, Timeout timeout) {
  dds::Sample<semfuse_srv_dds__Region_Request_> request;
  request->min = toPoint(box.min);
  request->max = toPoint(box.max);
  return call<semfuse_srv_dds__Region_Response_>(impl_->region, request, timeout, [](const auto& r) {
    RegionSummary summary;
    for (uint32_t i = 0; i < r.histogram._length; ++i) {
      const auto& h = r.histogram._buffer[i];
      summary.histogram.push_back({h.label, h.surface_voxels, h.area_m2});
    }
    summary.observed_voxels = r.observed_voxels;
    summary.occupied_voxels = r.occupied_voxels;
    summary.free_voxels = r.free_voxels;
    summary.occupancy = r.occupancy;
    return summary;
  });
}

CallResult<std::vector<ObjectInstance>> MapClient::objects(LabelId label, uint32_t min_voxels, Timeout timeout) {
  dds::Sample<semfuse_srv_dds__Objects_Request_> request;
  request->label = label;
  request->min_voxels = min_voxels;
  return call<semfuse_srv_dds__Objects_Response_>(impl_->objects, request, timeout, [](const auto& r) {
    std::vector<ObjectInstance> objects;
    for (uint32_t i = 0; i < r.objects._length; ++i) {
      const auto& o = r.objects._buffer[i];
      objects.push_back({o.id, o.label, fromPoint(o.bbox_min), fromPoint(o.bbox_max), fromPoint(o.centroid),
                         o.voxel_count, o.mean_confidence});
    }
    return objects;
  });
}

CallResult<MeshData> MapClient::mesh(const std::optional<Box>& box, Timeout timeout) {
  detail::MeshAssembly assembly;
  for (uint32_t chunk = 0; chunk < assembly.chunkCount(); ++chunk) {
    dds::Sample<semfuse_srv_dds__Mesh_Request_> request;
    request->use_box = box.has_value();
    if (box) {
      request->box_min = toPoint(box->min);
      request->box_max = toPoint(box->max);
    }
    request->mesh_id = assembly.meshId();
    request->chunk_index = chunk;
    auto reply = impl_->mesh.call(*request, timeout);
    if (!reply) return {Failure::kTimeout, reply.error()};
    const auto& r = *reply.value();
    if (!dds::replyOk(r)) {
      return {Failure::kServer, serverError(r)};
    }
    if (Status added = assembly.add(r, chunk); !added) return {Failure::kClient, added.error()};
  }
  auto mesh = std::move(assembly).finish();
  if (!mesh) return {Failure::kClient, mesh.error()};
  return std::move(mesh).value();
}

CallResult<ServerStatus> MapClient::stats(Timeout timeout) {
  return impl_->adminCall(semfuse_srv_dds__Admin_Request_Constants_STATS, "", timeout);
}
CallResult<ServerStatus> MapClient::save(const std::string& path, Timeout timeout) {
  return impl_->adminCall(semfuse_srv_dds__Admin_Request_Constants_SAVE, path, timeout);
}
CallResult<ServerStatus> MapClient::load(const std::string& path, Timeout timeout) {
  return impl_->adminCall(semfuse_srv_dds__Admin_Request_Constants_LOAD, path, timeout);
}
CallResult<ServerStatus> MapClient::reset(Timeout timeout) {
  return impl_->adminCall(semfuse_srv_dds__Admin_Request_Constants_RESET, "", timeout);
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

}  // namespace semfuse::client
