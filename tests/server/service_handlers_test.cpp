// The query services' handlers (server/core/src/service_handlers.*), called as the DDS adapter
// calls them but without DDS: on a small map of two labeled walls (label 5 at 1.0 m on the left
// of the camera, label 9 at 1.5 m on the right, voxels of 5 cm), what each answers and what it
// refuses, with which code and message.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "map_access.hpp"
#include "semfuse/core/legend.hpp"
#include "service_handlers.hpp"
#include "tiny_map.hpp"

namespace semfuse::server {
namespace {

const MapAccess& twoWalls() {
  static const VolumeAccess map(std::make_shared<const volume::LabeledVolume>(fuzz::makeTinyMap()),
                                *builtinLegend("voc"));
  return map;
}

QueryLimits smallLimits() {
  QueryLimits limits;
  limits.max_raycast_pixels = 64 * 64;
  limits.mesh_chunk_bytes = 1024;
  limits.max_points = 3;
  return limits;
}

RaycastRequest raycastOf(int width, int height, RaycastLayers layers) {
  return {Pose::Identity(), {width, height, 20.0, 20.0, (width - 1) / 2.0, (height - 1) / 2.0}, layers, 0.0F};
}

TEST(ServiceHandlers, RaycastSeesBothWallsWithTheirLabels) {
  auto reply = handleRaycast(raycastOf(32, 24, kDepthLayer | kLabelsLayer), twoWalls(), smallLimits());
  ASSERT_TRUE(reply.ok()) << reply.message;
  const cv::Mat& depth = reply.value.depth;
  const cv::Mat& labels = reply.value.labels;
  ASSERT_EQ(depth.size(), cv::Size(32, 24));
  EXPECT_NEAR(depth.at<float>(12, 4), 1.0f, 0.05f);
  EXPECT_EQ(labels.at<uint16_t>(12, 4), 5);
  EXPECT_NEAR(depth.at<float>(12, 27), 1.5f, 0.05f);
  EXPECT_EQ(labels.at<uint16_t>(12, 27), 9);
  EXPECT_TRUE(reply.value.normals.empty());
  EXPECT_TRUE(reply.value.color.empty());
}

TEST(ServiceHandlers, RaycastRefusesWhatItCannotRender) {
  auto too_large = handleRaycast(raycastOf(100, 100, kDepthLayer), twoWalls(), smallLimits());
  EXPECT_EQ(too_large.code, ReplyCode::kTooLarge);
  EXPECT_EQ(too_large.message, "raycast of 100x100 exceeds the limit of 4096 pixels (--max-raycast-pixels)");

  for (RaycastLayers layers : {0u, 32u}) {
    auto bad_layers = handleRaycast(raycastOf(32, 24, layers), twoWalls(), smallLimits());
    EXPECT_EQ(bad_layers.code, ReplyCode::kInvalidArgument);
    EXPECT_EQ(bad_layers.message,
              "layers must be a non-empty combination of LAYER_* bits (1..31), got " + std::to_string(layers));
  }

  RaycastRequest sheared = raycastOf(32, 24, kDepthLayer);
  sheared.camera_to_world.linear()(0, 1) = 0.5;
  auto not_rigid = handleRaycast(sheared, twoWalls(), smallLimits());
  EXPECT_EQ(not_rigid.code, ReplyCode::kInvalidArgument);
  EXPECT_NE(not_rigid.message.find("rotation"), std::string::npos) << not_rigid.message;

  RaycastRequest no_focal = raycastOf(32, 24, kDepthLayer);
  no_focal.intrinsics.fx = 0.0;
  EXPECT_EQ(handleRaycast(no_focal, twoWalls(), smallLimits()).code, ReplyCode::kInvalidArgument);
}

TEST(ServiceHandlers, LabelsAtProbesVoxels) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto reply = handleLabelsAt({{{-0.2, 0.0, 1.0}, {0.2, 0.0, 1.5}, {nan, 0.0, 1.0}}}, twoWalls(), smallLimits());
  ASSERT_TRUE(reply.ok()) << reply.message;
  ASSERT_EQ(reply.value.size(), 3u);
  EXPECT_TRUE(reply.value[0].observed);
  EXPECT_EQ(reply.value[0].label, 5);
  EXPECT_LT(std::abs(reply.value[0].tsdf), 0.05f);
  EXPECT_GT(reply.value[0].weight, 0.0f);
  EXPECT_TRUE(reply.value[1].observed);
  EXPECT_EQ(reply.value[1].label, 9);
  EXPECT_FALSE(reply.value[2].observed);

  auto too_many = handleLabelsAt({{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}}}, twoWalls(), smallLimits());
  EXPECT_EQ(too_many.code, ReplyCode::kTooLarge);
  EXPECT_EQ(too_many.message, "4 points exceed the limit of 3");
}

TEST(ServiceHandlers, RegionCountsWhatIsInTheBox) {
  auto reply = handleRegion({{-1.0, -1.0, 0.5}, {1.0, 1.0, 2.0}}, twoWalls());
  ASSERT_TRUE(reply.ok()) << reply.message;
  const RegionSummary& r = reply.value;
  EXPECT_GT(r.observed_voxels, 0u);
  EXPECT_EQ(r.occupied_voxels + r.free_voxels, r.observed_voxels);
  ASSERT_EQ(r.histogram.size(), 2u);  // in label order
  EXPECT_EQ(r.histogram[0].label, 5);
  EXPECT_EQ(r.histogram[1].label, 9);
  EXPECT_GT(r.histogram[0].surface_voxels, 0u);
  EXPECT_NEAR(r.histogram[0].area_m2, r.histogram[0].surface_voxels * 0.05 * 0.05, 1e-9);  // a sum of voxel areas

  auto inverted = handleRegion({{0.0, 0.0, 2.0}, {1.0, 1.0, 1.0}}, twoWalls());
  EXPECT_EQ(inverted.code, ReplyCode::kInvalidArgument);
  EXPECT_EQ(inverted.message, "box max must be >= min on every axis");
}

ObjectsRequest objectsOf(LabelId label) {
  ObjectsRequest request;
  request.label = label;
  request.min_voxels = 1;
  return request;
}

TEST(ServiceHandlers, ObjectsOfALabelInTheLegend) {
  auto all = handleObjects(objectsOf(kUnlabeled), twoWalls());
  ASSERT_TRUE(all.ok()) << all.message;
  ASSERT_EQ(all.value.size(), 2u);
  auto wall = handleObjects(objectsOf(9), twoWalls());
  ASSERT_TRUE(wall.ok()) << wall.message;
  ASSERT_EQ(wall.value.size(), 1u);
  EXPECT_EQ(wall.value[0].label, 9);
  EXPECT_NEAR(wall.value[0].centroid.z(), 1.5, 0.05);
  EXPECT_GT(wall.value[0].mean_confidence, 0.0f);

  auto unknown = handleObjects(objectsOf(99), twoWalls());
  EXPECT_EQ(unknown.code, ReplyCode::kInvalidArgument);
  EXPECT_EQ(unknown.message, "label 99 is not in the legend 'voc'");
}

TEST(ServiceHandlers, ObjectsKeepTheirIdsAndCarryTheirFigures) {
  auto tracker = makeObjectTracker(twoWalls().legend(), twoWalls().snapshot()->voxelSize());
  auto first = handleObjects(objectsOf(kUnlabeled), twoWalls(), *tracker);
  auto second = handleObjects(objectsOf(kUnlabeled), twoWalls(), *tracker);
  ASSERT_TRUE(first.ok() && second.ok()) << first.message << second.message;
  ASSERT_EQ(first.value.size(), 2u);
  ASSERT_EQ(second.value.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(first.value[i].id, second.value[i].id);
    EXPECT_EQ(first.value[i].label, second.value[i].label);
    const ObjectInstance& o = first.value[i];
    EXPECT_GT(o.area_m2, 0.0);
    // A wall: its oriented box is thin along one axis, and holds the centroid.
    EXPECT_LT(o.box_half_extents.minCoeff(), 0.05);
    EXPECT_TRUE((o.centroid.array() >= o.bbox_min.array()).all() && (o.centroid.array() <= o.bbox_max.array()).all());
    EXPECT_FALSE(o.fragment);
  }
  EXPECT_NE(first.value[0].id, first.value[1].id);
}

TEST(ServiceHandlers, ObjectsNearAPointAndTheirRefusals) {
  auto tracker = makeObjectTracker(twoWalls().legend(), twoWalls().snapshot()->voxelSize());
  auto all = handleObjects(objectsOf(kUnlabeled), twoWalls(), *tracker);
  ASSERT_TRUE(all.ok()) << all.message;
  ASSERT_EQ(all.value.size(), 2u);
  ObjectsRequest near = objectsOf(kUnlabeled);
  near.near = all.value[1].centroid;
  near.radius = 0.1;
  auto one = handleObjects(near, twoWalls(), *tracker);
  ASSERT_TRUE(one.ok()) << one.message;
  ASSERT_EQ(one.value.size(), 1u);
  EXPECT_EQ(one.value[0].id, all.value[1].id);

  near.near = Eigen::Vector3d(50.0, 50.0, 50.0);
  auto none = handleObjects(near, twoWalls(), *tracker);
  ASSERT_TRUE(none.ok()) << none.message;
  EXPECT_TRUE(none.value.empty());

  for (double radius : {0.0, -1.0, std::nan(""), 1000.0}) {
    near.radius = radius;
    auto bad = handleObjects(near, twoWalls(), *tracker);
    EXPECT_EQ(bad.code, ReplyCode::kInvalidArgument) << radius;
  }
}

TEST(ServiceHandlers, MeshOfOneObject) {
  auto tracker = makeObjectTracker(twoWalls().legend(), twoWalls().snapshot()->voxelSize());
  auto all = handleObjects(objectsOf(kUnlabeled), twoWalls(), *tracker);
  ASSERT_TRUE(all.ok()) << all.message;
  ASSERT_EQ(all.value.size(), 2u);
  HeldMeshes meshes;
  QueryLimits limits = smallLimits();
  limits.mesh_chunk_bytes = 1 << 24;
  auto whole = handleMesh({}, twoWalls(), meshes, limits, tracker.get());
  ASSERT_TRUE(whole.ok()) << whole.message;
  MeshRequest request;
  request.object_id = all.value[0].id;
  auto object = handleMesh(request, twoWalls(), meshes, limits, tracker.get());
  ASSERT_TRUE(object.ok()) << object.message;
  EXPECT_GT(object.value.face_count, 0u);
  EXPECT_LT(object.value.face_count, whole.value.face_count);

  request.object_id = 9999;
  auto missing = handleMesh(request, twoWalls(), meshes, limits, tracker.get());
  EXPECT_EQ(missing.code, ReplyCode::kNotFound);
  request.object_id = all.value[0].id;
  EXPECT_EQ(handleMesh(request, twoWalls(), meshes, limits).code, ReplyCode::kInvalidArgument);
}

TEST(ServiceHandlers, MeshIsFetchedInChunksOfTheHeldPly) {
  HeldMeshes meshes;
  auto first = handleMesh({}, twoWalls(), meshes, smallLimits());
  ASSERT_TRUE(first.ok()) << first.message;
  const MeshChunk& head = first.value;
  EXPECT_GT(head.vertex_count, 0u);
  EXPECT_GT(head.face_count, 0u);
  ASSERT_GT(head.total_bytes, 1024u);
  EXPECT_EQ(head.chunk_count, (head.total_bytes + 1023) / 1024);
  std::string ply(head.ply.begin(), head.ply.end());
  for (uint32_t i = 1; i < head.chunk_count; ++i) {
    auto next = handleMesh({std::nullopt, head.mesh_id, i}, twoWalls(), meshes, smallLimits());
    ASSERT_TRUE(next.ok()) << next.message;
    EXPECT_EQ(next.value.chunk_index, i);
    ply.append(next.value.ply.begin(), next.value.ply.end());
  }
  EXPECT_EQ(ply.size(), head.total_bytes);
  EXPECT_EQ(ply.rfind("ply\n", 0), 0u);

  auto beyond = handleMesh({std::nullopt, head.mesh_id, head.chunk_count}, twoWalls(), meshes, smallLimits());
  EXPECT_EQ(beyond.code, ReplyCode::kInvalidArgument);
  EXPECT_EQ(beyond.message, "chunk " + std::to_string(head.chunk_count) + " of a mesh with " +
                                std::to_string(head.chunk_count) + " chunks");

  // Four newer meshes push the first one out.
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(handleMesh({}, twoWalls(), meshes, smallLimits()).ok());
  auto gone = handleMesh({std::nullopt, head.mesh_id, 1}, twoWalls(), meshes, smallLimits());
  EXPECT_EQ(gone.code, ReplyCode::kNotFound);
  EXPECT_EQ(gone.message, "mesh " + std::to_string(head.mesh_id) + " is no longer held; request a new one (mesh_id 0)");

  auto inverted = handleMesh({Box{{0, 0, 2}, {1, 1, 1}}, 0, 0}, twoWalls(), meshes, smallLimits());
  EXPECT_EQ(inverted.code, ReplyCode::kInvalidArgument);
}

TEST(ServiceHandlers, AdminRunsTheCommandAndAnswersWithTheStatus) {
  std::string saved_to, loaded_from;
  std::vector<std::string> failures;
  int resets = 0;
  AdminActions actions;
  actions.map_file = "/maps/default.vdb";
  actions.save = [&](const std::string& path) {
    saved_to = path;
    return path == "/busy.vdb" ? Status(makeError(ErrorCode::kUnavailable, "a save is in progress")) : Status::Ok();
  };
  actions.load = [&](const std::string& path) {
    loaded_from = path;
    return path == "/gone.vdb" ? Status(makeError(ErrorCode::kNotFound, "no map file /gone.vdb")) : Status::Ok();
  };
  actions.reset = [&] {
    ++resets;
    return Status::Ok();
  };
  actions.status = [&] {
    ServerStatus status;
    status.server_id = "test";
    status.frames_integrated = static_cast<uint64_t>(resets);
    status.last_errors.resize(failures.size());
    return status;
  };
  actions.failed = [&](const Error& error) { failures.push_back(error.message); };

  auto save = handleAdmin({AdminCommand::kSave, ""}, actions);
  EXPECT_TRUE(save.ok());
  EXPECT_EQ(save.message, "saved");
  EXPECT_EQ(saved_to, "/maps/default.vdb");
  EXPECT_EQ(save.value.server_id, "test");

  auto load = handleAdmin({AdminCommand::kLoad, "/maps/other.vdb"}, actions);
  EXPECT_EQ(load.message, "loaded /maps/other.vdb");
  EXPECT_EQ(loaded_from, "/maps/other.vdb");

  auto reset = handleAdmin({AdminCommand::kReset, ""}, actions);
  EXPECT_EQ(reset.message, "map reset");
  EXPECT_EQ(reset.value.frames_integrated, 1u);  // the status after the command
  EXPECT_TRUE(failures.empty());

  // A failed command replies with the status of its error's code, and is recorded before the
  // reply takes the status.
  auto busy = handleAdmin({AdminCommand::kSave, "/busy.vdb"}, actions);
  EXPECT_EQ(busy.code, ReplyCode::kUnavailable);
  EXPECT_EQ(busy.message, "a save is in progress");
  EXPECT_EQ(busy.value.last_errors.size(), 1u);
  auto gone = handleAdmin({AdminCommand::kLoad, "/gone.vdb"}, actions);
  EXPECT_EQ(gone.code, ReplyCode::kNotFound);
  EXPECT_EQ(gone.message, "no map file /gone.vdb");

  actions.map_file.clear();
  auto nowhere = handleAdmin({AdminCommand::kLoad, ""}, actions);
  EXPECT_EQ(nowhere.code, ReplyCode::kInvalidArgument);
  EXPECT_EQ(nowhere.message, "load needs a path (the server has no --map)");
  EXPECT_EQ(failures, (std::vector<std::string>{"a save is in progress", "no map file /gone.vdb",
                                                "load needs a path (the server has no --map)"}));
  EXPECT_EQ(nowhere.value.server_id, "test");  // the status all the same
}

}  // namespace
}  // namespace semfuse::server
