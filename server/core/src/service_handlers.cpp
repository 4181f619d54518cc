#include "service_handlers.hpp"

#include <spdlog/spdlog.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "map_queries.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/objects/object_mesh.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/render/ply_writer.hpp"
#include "semfuse/render/raycast.hpp"

namespace semfuse::server {
namespace {

template <class T>
ServiceReply<T> refuse(ReplyCode code, std::string message) {
  return ServiceReply<T>::failure(code, std::move(message));
}

// A near query's largest radius: a room and more, not the whole map by accident of units.
constexpr double kMaxNearRadius = 100.0;

Status validBox(const Box& box) {
  if (!box.min.allFinite() || !box.max.allFinite()) return makeError("box corners must be finite");
  if ((box.max.array() < box.min.array()).any()) return makeError("box max must be >= min on every axis");
  return Status::Ok();
}

}  // namespace

ServiceReply<RaycastImages> handleRaycast(const RaycastRequest& request, const MapAccess& map,
                                          const QueryLimits& limits) {
  using Reply = RaycastImages;
  const PinholeIntrinsics& intrinsics = request.intrinsics;
  const uint64_t pixels = static_cast<uint64_t>(std::max(intrinsics.width, 0)) * std::max(intrinsics.height, 0);
  if (pixels > limits.max_raycast_pixels)
    return refuse<Reply>(ReplyCode::kTooLarge, "raycast of " + std::to_string(intrinsics.width) + "x" +
                                                   std::to_string(intrinsics.height) + " exceeds the limit of " +
                                                   std::to_string(limits.max_raycast_pixels) +
                                                   " pixels (--max-raycast-pixels)");
  if (Status ok = checkIntrinsics(intrinsics, kMaxImageSide); !ok)
    return refuse<Reply>(ReplyCode::kInvalidArgument, ok.error());
  if (Status ok = checkRigidPose(request.camera_to_world); !ok)
    return refuse<Reply>(ReplyCode::kInvalidArgument, ok.error());
  if (request.layers == 0 || request.layers > kAllLayers)
    return refuse<Reply>(
        ReplyCode::kInvalidArgument,
        "layers must be a non-empty combination of LAYER_* bits (1..31), got " + std::to_string(request.layers));

  render::RaycastOptions options;
  options.layers = request.layers;
  if (std::isfinite(request.max_range) && request.max_range > 0.0f) options.max_depth = request.max_range;
  // Copy the leaves in view under the map's shared lock (a few ms, where a snapshot of the whole
  // map took tens while cameras stream), render from the copy without the lock.
  std::optional<Result<render::PreparedRaycast>> prepared;
  map.read([&](const volume::LabeledVolume& volume) {
    prepared.emplace(render::prepareRaycast(volume, intrinsics, request.camera_to_world, options));
  });
  if (!prepared->ok()) return refuse<Reply>(ReplyCode::kInvalidArgument, prepared->error());
  auto images = render::raycast(std::move(*prepared).value());
  if (!images.ok()) return refuse<Reply>(ReplyCode::kInvalidArgument, images.error());
  render::RaycastImages& rendered = images.value();
  ServiceReply<Reply> reply;
  reply.value = {std::move(rendered.depth), std::move(rendered.normals), std::move(rendered.labels),
                 std::move(rendered.scores), std::move(rendered.color)};
  return reply;
}

ServiceReply<std::vector<VoxelSample>> handleLabelsAt(const LabelsAtRequest& request, const MapAccess& map,
                                                      const QueryLimits& limits) {
  using Reply = std::vector<VoxelSample>;
  if (request.points.size() > limits.max_points)
    return refuse<Reply>(ReplyCode::kTooLarge, std::to_string(request.points.size()) + " points exceed the limit of " +
                                                   std::to_string(limits.max_points));
  ServiceReply<Reply> reply;
  map.read([&](const volume::LabeledVolume& volume) { reply.value = sampleAt(volume, request.points); });
  return reply;
}

ServiceReply<RegionSummary> handleRegion(const Box& box, const MapAccess& map) {
  if (Status ok = validBox(box); !ok) return refuse<RegionSummary>(ReplyCode::kInvalidArgument, ok.error());
  ServiceReply<RegionSummary> reply;
  reply.value = summarizeRegion(*map.snapshot(), box.min, box.max);
  return reply;
}

ServiceReply<std::vector<ObjectInstance>> handleObjects(const ObjectsRequest& request, const MapAccess& map,
                                                        objects::ObjectTracker& tracker) {
  using Reply = std::vector<ObjectInstance>;
  const LabelLegend& legend = map.legend();
  if (request.label != kUnlabeled && !legend.contains(request.label))
    return refuse<Reply>(ReplyCode::kInvalidArgument,
                         "label " + std::to_string(request.label) + " is not in the legend '" + legend.name + "'");
  if (request.near && (!request.near->allFinite() || !std::isfinite(request.radius) || request.radius <= 0.0 ||
                       request.radius > kMaxNearRadius))
    return refuse<Reply>(ReplyCode::kInvalidArgument, "near needs a finite point and a radius in (0, " +
                                                          std::to_string(int(kMaxNearRadius)) + "] m");
  if (!std::isfinite(request.max_age_s) || request.max_age_s < 0.0)
    return refuse<Reply>(ReplyCode::kInvalidArgument, "max_age must be 0 or more seconds");
  std::shared_ptr<const objects::ObjectSet> set;
  if (request.max_age_s > 0.0) {
    const std::chrono::duration<double> max_age(request.max_age_s);
    // Without waiting while an update runs, when the last set will do; else after it.
    const objects::ObjectTracker::Latest latest = tracker.latest();
    if (latest.set && std::chrono::steady_clock::now() - latest.current_at <= max_age) set = latest.set;
    else set = tracker.recentOrOf(max_age, [&map] { return map.snapshot(); });
  } else {
    set = tracker.objectsOf(map.snapshot());
  }
  ServiceReply<Reply> reply;
  reply.value = selectObjects(*set, request, set->voxel_size);
  return reply;
}

ServiceReply<std::vector<ObjectInstance>> handleObjects(const ObjectsRequest& request, const MapAccess& map) {
  auto tracker = makeObjectTracker(map.legend(), map.snapshot()->voxelSize());
  return handleObjects(request, map, *tracker);
}

std::unique_ptr<objects::ObjectTracker> makeObjectTracker(const LabelLegend& legend, double voxel_size,
                                                          objects::ObjectParams params) {
  return std::make_unique<objects::ObjectTracker>(std::move(params), legend, voxel_size);
}

ServiceReply<MeshChunk> handleMesh(const MeshRequest& request, const MapAccess& map, HeldMeshes& meshes,
                                   const QueryLimits& limits, objects::ObjectTracker* tracker) {
  std::shared_ptr<const std::string> ply;
  uint64_t mesh_id = request.mesh_id;
  uint32_t vertices = 0, faces = 0;
  if (mesh_id == 0 && request.object_id != 0) {
    if (!tracker) return refuse<MeshChunk>(ReplyCode::kInvalidArgument, "this map keeps no objects");
    const auto snapshot = map.snapshot();
    const auto set = tracker->objectsOf(snapshot);
    const objects::TrackedObject* object = set->find(request.object_id);
    if (!object || !set->ids)
      return refuse<MeshChunk>(ReplyCode::kNotFound, "the map has no object " + std::to_string(request.object_id));
    auto mesh =
        objects::objectMesh(*snapshot, *set->ids, object->id, object->figures.bbox_min, object->figures.bbox_max);
    if (!mesh.ok()) return refuse<MeshChunk>(ReplyCode::kInternal, mesh.error());
    auto bytes = render::plyBytes(mesh.value(), map.legend());
    if (!bytes.ok()) return refuse<MeshChunk>(ReplyCode::kInternal, bytes.error());
    vertices = static_cast<uint32_t>(mesh.value().vertices.size());
    faces = static_cast<uint32_t>(mesh.value().triangles.size());
    ply = std::make_shared<const std::string>(std::move(bytes).value());
    mesh_id = meshes.hold(ply);
  } else if (mesh_id == 0) {
    render::MeshOptions options;
    if (request.box) {
      if (Status ok = validBox(*request.box); !ok) return refuse<MeshChunk>(ReplyCode::kInvalidArgument, ok.error());
      options.bounds = render::WorldBounds{request.box->min, request.box->max};
    }
    auto mesh = render::extractMesh(*map.snapshot(), options);
    if (!mesh.ok()) return refuse<MeshChunk>(ReplyCode::kInvalidArgument, mesh.error());
    auto bytes = render::plyBytes(mesh.value(), map.legend());
    if (!bytes.ok()) return refuse<MeshChunk>(ReplyCode::kInternal, bytes.error());
    vertices = static_cast<uint32_t>(mesh.value().vertices.size());
    faces = static_cast<uint32_t>(mesh.value().triangles.size());
    ply = std::make_shared<const std::string>(std::move(bytes).value());
    mesh_id = meshes.hold(ply);
  } else {
    ply = meshes.find(mesh_id);
    if (!ply)
      return refuse<MeshChunk>(ReplyCode::kNotFound,
                               "mesh " + std::to_string(mesh_id) + " is no longer held; request a new one (mesh_id 0)");
  }
  const size_t chunk = std::max<uint32_t>(limits.mesh_chunk_bytes, 1024);
  const uint32_t chunks = static_cast<uint32_t>(std::max<size_t>(1, (ply->size() + chunk - 1) / chunk));
  if (request.chunk_index >= chunks)
    return refuse<MeshChunk>(ReplyCode::kInvalidArgument, "chunk " + std::to_string(request.chunk_index) +
                                                              " of a mesh with " + std::to_string(chunks) + " chunks");
  const size_t begin = static_cast<size_t>(request.chunk_index) * chunk;
  const size_t length = std::min(chunk, ply->size() - begin);
  ServiceReply<MeshChunk> reply;
  MeshChunk& out = reply.value;
  out.mesh_id = mesh_id;
  out.chunk_index = request.chunk_index;
  out.chunk_count = chunks;
  out.total_bytes = ply->size();
  out.vertex_count = vertices;
  out.face_count = faces;
  const auto* bytes = reinterpret_cast<const uint8_t*>(ply->data());
  out.ply.assign(bytes + begin, bytes + begin + length);
  return reply;
}

ServiceReply<ServerStatus> handleAdmin(const AdminRequest& request, const AdminActions& actions) {
  const std::string file = request.path.empty() ? actions.map_file : request.path;
  Status result;
  std::string done;
  switch (request.command) {
    case AdminCommand::kStats:
      break;
    case AdminCommand::kSave:
      result = actions.save(file);
      done = "saved";
      break;
    case AdminCommand::kLoad:
      result = file.empty() ? makeError(ErrorCode::kInvalidArgument, "load needs a path (the server has no --map)")
                            : actions.load(file);
      done = "loaded " + file;
      break;
    case AdminCommand::kReset:
      result = actions.reset();
      done = "map reset";
      break;
  }
  ServiceReply<ServerStatus> reply;
  if (!result.ok()) {
    reply.code = replyCodeOf(result.errorCode());
    reply.message = result.error();
    actions.failed(result.errorInfo());
  } else {
    if (!done.empty()) spdlog::info("admin: {}", done);
    reply.message = done;
  }
  reply.value = actions.status();
  return reply;
}

}  // namespace semfuse::server
