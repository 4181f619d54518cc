#include "services.hpp"

#include <spdlog/spdlog.h>
#include <algorithm>
#include <functional>

#include "map_queries.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/render/ply_writer.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/image_message.hpp"
#include "semfuse/wire/reply_status.hpp"
#include "semfuse/wire/validation.hpp"
#include "tbb_worker_names.hpp"

namespace semfuse::server {
namespace {
constexpr int32_t kOk = semfuse_srv_dds__Status_Constants_OK;
constexpr int32_t kInvalid = semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT;
constexpr int32_t kNotFound = semfuse_srv_dds__Status_Constants_NOT_FOUND;
constexpr int32_t kInternal = semfuse_srv_dds__Status_Constants_INTERNAL;
constexpr int32_t kTooLarge = semfuse_srv_dds__Status_Constants_TOO_LARGE;
constexpr size_t kMeshesKept = 4;
constexpr size_t kMaxPointsPerQuery = 1u << 20;

Eigen::Vector3d toEigen(const geometry_msgs_msg_dds__Point_& p) { return {p.x, p.y, p.z}; }
geometry_msgs_msg_dds__Point_ toPoint(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

Status validBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  if (!min.allFinite() || !max.allFinite()) return makeError("box corners must be finite");
  if ((max.array() < min.array()).any()) return makeError("box max must be >= min on every axis");
  return Status::Ok();
}

// A service's handler, run on that service's own thread (dds::RpcServer): the TBB workers that
// help that thread are named first (tbb_worker_names.hpp).
template <class Request, class Reply>
std::function<void(const Request&, Reply&)> onServiceThread(Services* services,
                                                            void (Services::*handle)(const Request&, Reply&)) {
  return [services, handle](const Request& request, Reply& reply) {
    nameTbbWorkers();
    (services->*handle)(request, reply);
  };
}
}  // namespace

Services::Services(const dds::Participant& participant, const ServerConfig& config, Mapper& mapper, FusionLoop& fusion,
                   ServerState& state, SnapshotFn snapshot, SaveFn save)
    : config_(config),
      mapper_(mapper),
      fusion_(fusion),
      state_(state),
      snapshot_(std::move(snapshot)),
      save_(std::move(save)) {
  namespace topics = dds::topics;
  raycast_server_ =
      std::make_unique<dds::RpcServer<semfuse_srv_dds__Raycast_Request_, semfuse_srv_dds__Raycast_Response_>>(
          participant, topics::raycast(), onServiceThread(this, &Services::raycast));
  labels_at_server_ =
      std::make_unique<dds::RpcServer<semfuse_srv_dds__LabelsAt_Request_, semfuse_srv_dds__LabelsAt_Response_>>(
          participant, topics::labelsAt(), onServiceThread(this, &Services::labelsAt));
  region_server_ =
      std::make_unique<dds::RpcServer<semfuse_srv_dds__Region_Request_, semfuse_srv_dds__Region_Response_>>(
          participant, topics::region(), onServiceThread(this, &Services::region));
  objects_server_ =
      std::make_unique<dds::RpcServer<semfuse_srv_dds__Objects_Request_, semfuse_srv_dds__Objects_Response_>>(
          participant, topics::objects(), onServiceThread(this, &Services::objects));
  mesh_server_ = std::make_unique<dds::RpcServer<semfuse_srv_dds__Mesh_Request_, semfuse_srv_dds__Mesh_Response_>>(
      participant, topics::mesh(), onServiceThread(this, &Services::mesh));
  admin_server_ = std::make_unique<dds::RpcServer<semfuse_srv_dds__Admin_Request_, semfuse_srv_dds__Admin_Response_>>(
      participant, topics::admin(), onServiceThread(this, &Services::admin));
}

Services::~Services() = default;

template <class Reply>
void Services::refuse(Reply& reply, int32_t code, const std::string& service, const std::string& message) {
  dds::setReplyStatus(reply, code, message);
  state_.reject(reason::kInvalidQuery, "", "query " + service, message);
}

void Services::raycast(const semfuse_srv_dds__Raycast_Request_& request, semfuse_srv_dds__Raycast_Response_& reply) {
  PinholeIntrinsics intrinsics{static_cast<int>(std::min<uint32_t>(request.intrinsics.width, 1u << 30)),
                               static_cast<int>(std::min<uint32_t>(request.intrinsics.height, 1u << 30)),
                               request.intrinsics.fx,
                               request.intrinsics.fy,
                               request.intrinsics.cx,
                               request.intrinsics.cy};
  const uint64_t pixels = static_cast<uint64_t>(request.intrinsics.width) * request.intrinsics.height;
  if (pixels > config_.max_raycast_pixels)
    return refuse(reply, kTooLarge, "raycast",
                  "raycast of " + std::to_string(request.intrinsics.width) + "x" +
                      std::to_string(request.intrinsics.height) + " exceeds the limit of " +
                      std::to_string(config_.max_raycast_pixels) + " pixels (--max-raycast-pixels)");
  if (Status ok = checkIntrinsics(intrinsics, wire::kMaxImageSide); !ok)
    return refuse(reply, kInvalid, "raycast", ok.error());
  const Pose pose = wire::poseFromRowMajor(request.camera_to_world);
  if (Status ok = checkRigidPose(pose); !ok) return refuse(reply, kInvalid, "raycast", ok.error());
  if (request.layers == 0 || request.layers > kAllLayers)
    return refuse(
        reply, kInvalid, "raycast",
        "layers must be a non-empty combination of LAYER_* bits (1..31), got " + std::to_string(request.layers));

  render::RaycastOptions options;
  options.layers = request.layers;
  if (std::isfinite(request.max_range) && request.max_range > 0.0f) options.max_depth = request.max_range;
  // Copy the leaves in view under the map's shared lock (a few ms, where a snapshot of the whole
  // map took tens while cameras stream), render from the copy without the lock.
  auto prepared = mapper_.read(
      [&](const volume::LabeledVolume& volume) { return render::prepareRaycast(volume, intrinsics, pose, options); });
  if (!prepared.ok()) return refuse(reply, kInvalid, "raycast", prepared.error());
  auto images = render::raycast(std::move(prepared.value()));
  if (!images.ok()) return refuse(reply, kInvalid, "raycast", images.error());
  const auto& im = images.value();
  wire::fillImageMessage(reply.depth, im.depth, "32FC1");
  wire::fillImageMessage(reply.normals, im.normals, "32FC3");
  wire::fillImageMessage(reply.labels, im.labels, "16UC1");
  wire::fillImageMessage(reply.confidence, im.scores, "32FC1");
  wire::fillImageMessage(reply.color, im.color, "rgb8");
  dds::setReplyStatus(reply, kOk, "");
}

void Services::labelsAt(const semfuse_srv_dds__LabelsAt_Request_& request, semfuse_srv_dds__LabelsAt_Response_& reply) {
  if (request.points._length > kMaxPointsPerQuery)
    return refuse(
        reply, kTooLarge, "labels_at",
        std::to_string(request.points._length) + " points exceed the limit of " + std::to_string(kMaxPointsPerQuery));
  std::vector<Eigen::Vector3d> points;
  points.reserve(request.points._length);
  for (uint32_t i = 0; i < request.points._length; ++i) points.push_back(toEigen(request.points._buffer[i]));
  auto samples = mapper_.read([&](const volume::LabeledVolume& v) { return sampleAt(v, points); });
  dds::resizeSequence(reply.samples, samples.size());
  for (size_t i = 0; i < samples.size(); ++i)
    reply.samples._buffer[i] = {samples[i].observed, samples[i].label, samples[i].score, samples[i].tsdf,
                                samples[i].weight};
  dds::setReplyStatus(reply, kOk, "");
}

void Services::region(const semfuse_srv_dds__Region_Request_& request, semfuse_srv_dds__Region_Response_& reply) {
  const Eigen::Vector3d min = toEigen(request.min), max = toEigen(request.max);
  if (Status ok = validBox(min, max); !ok) return refuse(reply, kInvalid, "region", ok.error());
  auto summary = summarizeRegion(*mapper_.snapshot(), min, max);
  dds::resizeSequence(reply.histogram, summary.labels.size());
  size_t i = 0;
  for (const auto& [label, area] : summary.labels)
    reply.histogram._buffer[i++] = {label, area.surface_voxels, area.area_m2};
  reply.observed_voxels = summary.observed_voxels;
  reply.occupied_voxels = summary.occupied_voxels;
  reply.free_voxels = summary.free_voxels;
  reply.occupancy = summary.occupancy;
  dds::setReplyStatus(reply, kOk, "");
}

void Services::objects(const semfuse_srv_dds__Objects_Request_& request, semfuse_srv_dds__Objects_Response_& reply) {
  if (request.label != kUnlabeled && !mapper_.legend().contains(request.label))
    return refuse(reply, kInvalid, "objects",
                  "label " + std::to_string(request.label) + " is not in the legend '" + mapper_.legend().name + "'");
  auto found = findObjects(*mapper_.snapshot(), mapper_.legend(), request.label, request.min_voxels);
  dds::resizeSequence(reply.objects, found.size());
  for (size_t i = 0; i < found.size(); ++i) {
    auto& o = reply.objects._buffer[i];
    o.id = found[i].id;
    o.label = found[i].label;
    o.bbox_min = toPoint(found[i].bbox_min);
    o.bbox_max = toPoint(found[i].bbox_max);
    o.centroid = toPoint(found[i].centroid);
    o.voxel_count = found[i].voxel_count;
    o.mean_confidence = found[i].mean_score;
  }
  dds::setReplyStatus(reply, kOk, "");
}

void Services::mesh(const semfuse_srv_dds__Mesh_Request_& request, semfuse_srv_dds__Mesh_Response_& reply) {
  std::shared_ptr<const std::string> ply;
  uint64_t mesh_id = request.mesh_id;
  uint32_t vertices = 0, faces = 0;
  if (mesh_id == 0) {
    render::MeshOptions options;
    if (request.use_box) {
      const Eigen::Vector3d min = toEigen(request.box_min), max = toEigen(request.box_max);
      if (Status ok = validBox(min, max); !ok) return refuse(reply, kInvalid, "mesh", ok.error());
      options.bounds = render::WorldBounds{min, max};
    }
    auto mesh = render::extractMesh(*mapper_.snapshot(), options);
    if (!mesh.ok()) return refuse(reply, kInvalid, "mesh", mesh.error());
    auto bytes = render::plyBytes(mesh.value(), mapper_.legend());
    if (!bytes.ok()) return refuse(reply, kInternal, "mesh", bytes.error());
    vertices = static_cast<uint32_t>(mesh.value().vertices.size());
    faces = static_cast<uint32_t>(mesh.value().triangles.size());
    ply = std::make_shared<const std::string>(std::move(bytes).value());
    std::lock_guard lock(meshes_mutex_);
    mesh_id = next_mesh_id_++;
    meshes_[mesh_id] = ply;
    while (meshes_.size() > kMeshesKept) meshes_.erase(meshes_.begin());
  } else {
    std::lock_guard lock(meshes_mutex_);
    auto it = meshes_.find(mesh_id);
    if (it == meshes_.end()) {
      dds::setReplyStatus(reply, kNotFound,
                          "mesh " + std::to_string(mesh_id) + " is no longer held; request a new one (mesh_id 0)");
      return;
    }
    ply = it->second;
  }
  const size_t chunk = std::max<uint32_t>(config_.mesh_chunk_bytes, 1024);
  const uint32_t chunks = static_cast<uint32_t>(std::max<size_t>(1, (ply->size() + chunk - 1) / chunk));
  if (request.chunk_index >= chunks) {
    dds::setReplyStatus(
        reply, kInvalid,
        "chunk " + std::to_string(request.chunk_index) + " of a mesh with " + std::to_string(chunks) + " chunks");
    return;
  }
  const size_t begin = static_cast<size_t>(request.chunk_index) * chunk;
  const size_t length = std::min(chunk, ply->size() - begin);
  reply.mesh_id = mesh_id;
  reply.chunk_index = request.chunk_index;
  reply.chunk_count = chunks;
  reply.total_bytes = ply->size();
  reply.vertex_count = vertices;
  reply.face_count = faces;
  dds::setSequence(reply.ply, reinterpret_cast<const uint8_t*>(ply->data() + begin), length);
  dds::setReplyStatus(reply, kOk, "");
}

void Services::admin(const semfuse_srv_dds__Admin_Request_& request, semfuse_srv_dds__Admin_Response_& reply) {
  using namespace std::chrono_literals;
  const std::string path = request.path ? request.path : "";
  Status result;
  std::string done;
  switch (request.command) {
    case semfuse_srv_dds__Admin_Request_Constants_STATS:
      break;
    case semfuse_srv_dds__Admin_Request_Constants_SAVE:
      result = save_(path.empty() ? config_.map_file : path);
      done = "saved";
      break;
    case semfuse_srv_dds__Admin_Request_Constants_LOAD: {
      const std::string file = path.empty() ? config_.map_file : path;
      if (file.empty()) return refuse(reply, kInvalid, "admin", "load needs a path (the server has no --map)");
      result = fusion_.runOnFusionThread([this, file] { return mapper_.load(file); }, 60s);
      done = "loaded " + file;
      break;
    }
    case semfuse_srv_dds__Admin_Request_Constants_RESET:
      result = fusion_.runOnFusionThread(
          [this] {
            mapper_.reset();
            return Status::Ok();
          },
          60s);
      done = "map reset";
      break;
    default:
      return refuse(reply, kInvalid, "admin",
                    "unknown admin command " + std::to_string(request.command) + " (0 stats, 1 save, 2 load, 3 reset)");
  }
  if (!result.ok()) {
    dds::setReplyStatus(reply, wire::replyStatusOf(result.errorCode()), result.error());
    state_.errors.record("admin", result.error());
    state_.touch();
  } else {
    if (!done.empty()) spdlog::info("admin: {}", done);
    dds::setReplyStatus(reply, kOk, done);
  }
  fillStatusMessage(snapshot_(), reply.server_status);
}

}  // namespace semfuse::server
