// semfuse-server as a real process over loopback DDS: a camera stream of the synthetic room with
// poses, ground-truth segmentations (every third one late and out of order), bad input of every
// kind, queries, and a restart from the saved map.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "semfuse/client/map_client.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/volume/map_file.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr int kFrames = 36;
constexpr double kVoxel = 0.02;

synthetic::SequenceConfig sequenceConfig() {
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);  // 320x240 keeps the test quick
  config.trajectory.frame_count = kFrames;
  config.camera_id = "cam0";
  return config;
}

std::vector<std::string> serverArgs(const std::filesystem::path& map) {
  return {"--legend",
          "synthetic",
          "--voxel-size",
          std::to_string(kVoxel),
          "--truncation",
          std::to_string(4 * kVoxel),
          "--map",
          map.string(),
          "--autosave-period",
          "0",
          "--pending-timeout",
          "2",
          "--queue-per-camera",
          "64",
          "--max-queue-wait",
          "0"};
}

void publishFrame(ServerHarness& h, const Frame& frame) {
  auto encoded = wire::encodeFrame(frame);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
}

void publishSegmentation(ServerHarness& h, const Segmentation& segmentation) {
  auto encoded = wire::encodeSegmentation(segmentation);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  ASSERT_TRUE(h.segmentations().write(encoded.value().msg()).ok());
}

semfuse_srv_dds__Raycast_Request_ raycastRequest(const Pose& pose, const PinholeIntrinsics& k, uint32_t layers) {
  semfuse_srv_dds__Raycast_Request_ request{};
  wire::poseToRowMajor(pose, request.camera_to_world);
  request.intrinsics = {static_cast<uint32_t>(k.width), static_cast<uint32_t>(k.height), k.fx, k.fy, k.cx, k.cy};
  request.layers = layers;
  return request;
}

cv::Mat imageOf(const sensor_msgs_msg_dds__Image_& image, int type) {
  return cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), type, image.data._buffer).clone();
}

class ServerEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("semfuse_e2e_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(ServerEndToEnd, FusesLateSegmentationsAnswersQueriesAndResumesAfterRestart) {
  const std::filesystem::path map = dir_ / "map.vdb";
  ServerHarness h(serverTestDomain());
  h.startServer(serverArgs(map));
  synthetic::SyntheticSequence sequence(sequenceConfig());

  // Stream: frames paced by the pose the server publishes for each; segmentations of two
  // frames in three right away, every third one held back and sent later, newest first.
  std::vector<Segmentation> held;
  for (int i = 0; i < kFrames; ++i) {
    auto both = sequence.frameWithGroundTruth(i);
    ASSERT_TRUE(both.ok()) << both.error();
    publishFrame(h, both.value().first);
    ASSERT_TRUE(h.waitPose("cam0", static_cast<uint64_t>(i), 20s)) << "no pose for frame " << i;
    if (i % 3 == 0) held.push_back(both.value().second);
    else publishSegmentation(h, both.value().second);
    if (held.size() == 4 || i == kFrames - 1) {
      std::reverse(held.begin(), held.end());
      for (const auto& late : held) publishSegmentation(h, late);
      held.clear();
    }
  }

  auto status = h.waitStatus(
      [](const auto& s) { return s.frames_integrated == kFrames && s.segmentations_integrated == kFrames; }, 30s);
  ASSERT_NE(status.get(), nullptr);
  EXPECT_EQ(status->frames_received, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(status->frames_integrated, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(status->segmentations_integrated, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(counterTotal(status->dropped), 0u);
  EXPECT_EQ(counterTotal(status->rejected), 0u);
  // Where the time went: every frame decoded, queued, tracked and integrated once (the server
  // integrates every frame here, --max-queue-wait 0).
  std::map<std::string, const semfuse_msg_dds__StageTiming_*> stages;
  for (uint32_t i = 0; i < status->stages._length; ++i)
    stages[status->stages._buffer[i].stage] = &status->stages._buffer[i];
  for (const char* stage : {"frame_decode", "frame_queue", "track", "integrate"}) {
    ASSERT_TRUE(stages.count(stage)) << stage;
    EXPECT_EQ(stages[stage]->count, static_cast<uint64_t>(kFrames)) << stage;
    EXPECT_GT(stages[stage]->max_ms, 0.0F) << stage;
    EXPECT_LE(stages[stage]->p50_ms, stages[stage]->p95_ms) << stage;
    EXPECT_LE(stages[stage]->p95_ms, stages[stage]->max_ms) << stage;
  }
  // A pose is published before its frame is integrated, so a segmentation sent once the pose
  // came may still be fused with its frame. Of each four held back, the first three were sent at
  // least three poses after their frame's, when integration (at most 2 frames behind tracking
  // here) had taken that frame: a label pass each.
  ASSERT_TRUE(stages.count("late_labels"));
  EXPECT_GE(stages["late_labels"]->count, static_cast<uint64_t>(kFrames / 4));
  EXPECT_LE(stages["late_labels"]->count, static_cast<uint64_t>(kFrames));

  // Raycast from a pose between two frames: labels agree with the ground truth.
  const Pose view_pose = sequence.config().trajectory.pose(10.5);
  const PinholeIntrinsics k = sequence.config().intrinsics;
  auto request = raycastRequest(
      view_pose, k,
      semfuse_srv_dds__Raycast_Request_Constants_LAYER_DEPTH | semfuse_srv_dds__Raycast_Request_Constants_LAYER_LABELS);
  auto reply = h.raycast().call(request, 20s);
  ASSERT_TRUE(reply.ok()) << reply.error();
  ASSERT_EQ(reply.value()->status, 0) << dds::replyMessage(*reply.value());
  const cv::Mat labels = imageOf(reply.value()->labels, CV_16UC1);
  auto truth = synthetic::renderView(sequence.scene(), k, view_pose);
  ASSERT_TRUE(truth.ok());
  int valid = 0, agree = 0;
  for (int v = 0; v < labels.rows; ++v)
    for (int u = 0; u < labels.cols; ++u) {
      const uint16_t expected = truth.value().labels.at<uint16_t>(v, u);
      const uint16_t got = labels.at<uint16_t>(v, u);
      if (expected == 0 || got == 0) continue;
      ++valid;
      agree += expected == got;
    }
  ASSERT_GT(valid, labels.rows * labels.cols / 2);
  EXPECT_GE(static_cast<double>(agree) / valid, 0.95) << agree << " of " << valid;

  // Objects over DDS: the table is one object (its top and legs), ids are kept between two calls,
  // the near filter finds it, and its mesh is its own: smaller than the map's, inside its box.
  client::MapClient objects_client(h.participant());
  ObjectsRequest tables;
  tables.label = synthetic::labels::kTable;
  auto table = objects_client.objects(tables, 30s);
  ASSERT_TRUE(table.ok()) << table.error();
  ASSERT_EQ(table.value().size(), 1u);
  const ObjectInstance& t = table.value()[0];
  EXPECT_GT(t.area_m2, 0.5);  // the top alone is 1.2 x 0.8 m
  EXPECT_NEAR(t.bbox_max.z(), 0.75, 0.05);
  // The frames that saw it: of this camera, among those sent, the best of them with the table's
  // centre in its image (the orbit sees the table from every frame, so all frames count).
  EXPECT_GT(t.frame_count, static_cast<uint32_t>(kFrames / 2));
  EXPECT_LE(t.frame_count, static_cast<uint32_t>(kFrames));
  ASSERT_FALSE(t.frames.empty());
  EXPECT_LE(t.frames.size(), 16u);
  for (const FrameRef& f : t.frames) {
    EXPECT_EQ(f.camera_id, "cam0");
    EXPECT_LT(f.seq, static_cast<uint64_t>(kFrames));
  }
  {
    const Pose seen_from = sequence.config().trajectory.pose(static_cast<double>(t.frames[0].seq));
    const Eigen::Vector3d in_camera = seen_from.inverse() * t.centroid;
    const PinholeIntrinsics& intrinsics = sequence.config().intrinsics;
    ASSERT_GT(in_camera.z(), 0.0);
    const double u = intrinsics.fx * in_camera.x() / in_camera.z() + intrinsics.cx;
    const double v = intrinsics.fy * in_camera.y() / in_camera.z() + intrinsics.cy;
    EXPECT_TRUE(u >= 0 && u < intrinsics.width && v >= 0 && v < intrinsics.height) << u << ", " << v;
  }
  ObjectsRequest everything;
  auto all_first = objects_client.objects(everything, 30s);
  auto all_second = objects_client.objects(everything, 30s);
  ASSERT_TRUE(all_first.ok() && all_second.ok());
  ASSERT_EQ(all_first.value().size(), all_second.value().size());
  for (std::size_t i = 0; i < all_first.value().size(); ++i)
    EXPECT_EQ(all_first.value()[i].id, all_second.value()[i].id);
  ObjectsRequest near = everything;
  near.near = t.centroid + Eigen::Vector3d(0.0, 0.0, 0.1);
  near.radius = 0.4;
  auto close = objects_client.objects(near, 30s);
  ASSERT_TRUE(close.ok()) << close.error();
  EXPECT_TRUE(
      std::any_of(close.value().begin(), close.value().end(), [&](const ObjectInstance& o) { return o.id == t.id; }));
  EXPECT_LT(close.value().size(), all_first.value().size());
  auto table_mesh = objects_client.mesh(std::nullopt, 30s, t.id);
  auto whole_mesh = objects_client.mesh(std::nullopt, 30s);
  ASSERT_TRUE(table_mesh.ok() && whole_mesh.ok()) << table_mesh.error() << whole_mesh.error();
  EXPECT_GT(table_mesh.value().face_count, 1000u);
  EXPECT_LT(table_mesh.value().face_count, whole_mesh.value().face_count / 4);
  // The objects' changes on rt/semfuse/object_events: subscribing after the queries still gets
  // the first update (the server keeps its last 16), in which every object appeared.
  const std::vector<ObjectEvents> updates = objects_client.takeObjectEvents(10s);
  ASSERT_FALSE(updates.empty());
  const ObjectEvents& first = updates.front();
  EXPECT_EQ(first.update, 1u);
  EXPECT_GE(first.object_count, all_first.value().size());
  EXPECT_EQ(first.events.size(), first.object_count);
  EXPECT_TRUE(std::all_of(first.events.begin(), first.events.end(),
                          [](const ObjectEvent& e) { return e.kind == ObjectEventKind::kAppeared; }));
  EXPECT_TRUE(
      std::any_of(first.events.begin(), first.events.end(), [&](const ObjectEvent& e) { return e.id == t.id; }));
  EXPECT_EQ(objects_client.rejectedObjectEvents(), 0u);
  auto no_object = objects_client.mesh(std::nullopt, 30s, 999999);
  ASSERT_FALSE(no_object.ok());
  EXPECT_EQ(no_object.errorCode(), ErrorCode::kNotFound) << no_object.error();

  // Save through the admin service; every surface voxel of the saved map against the scene.
  h.saveMap();
  if (::testing::Test::HasFatalFailure()) return;
  auto loaded = volume::loadMap(map);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const auto& volume = loaded.value().volume;
  uint64_t surface = 0, correct = 0;
  for (auto it = volume.geometryGrid().cbeginValueOn(); it; ++it) {
    const auto voxel = volume::unpackVoxel(*it);
    if (!it.isVoxelValue() || voxel.weight <= 0 || std::abs(voxel.tsdf) >= 0.5 * kVoxel) continue;
    ++surface;
    correct += voxel.label == sequence.scene().nearestSurface(volume.indexToWorld(it.getCoord())).label;
  }
  ASSERT_GT(surface, 10000u);
  EXPECT_GE(static_cast<double>(correct) / surface, 0.98) << correct << " of " << surface;

  // Restart from the same map: the same view renders the same depth and labels, bit for bit.
  auto before = h.raycast().call(request, 20s);
  ASSERT_TRUE(before.ok());
  EXPECT_EQ(h.stopServer(), 0);
  h.startServer(serverArgs(map));
  auto after = h.raycast().call(request, 20s);
  ASSERT_TRUE(after.ok()) << after.error();
  ASSERT_EQ(after.value()->status, 0) << dds::replyMessage(*after.value());
  const cv::Mat depth_before = imageOf(before.value()->depth, CV_32FC1),
                depth_after = imageOf(after.value()->depth, CV_32FC1);
  EXPECT_EQ(cv::norm(depth_before, depth_after, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::countNonZero(imageOf(before.value()->labels, CV_16UC1) != imageOf(after.value()->labels, CV_16UC1)), 0);
  // The frames that saw an object are not saved with the map: the restarted server, which has
  // fused no frame yet, knows the table but no frame of it.
  client::MapClient restarted(h.participant());
  auto table_after = restarted.objects(tables, 30s);
  ASSERT_TRUE(table_after.ok()) << table_after.error();
  ASSERT_EQ(table_after.value().size(), 1u);
  EXPECT_EQ(table_after.value()[0].frame_count, 0u);
  EXPECT_TRUE(table_after.value()[0].frames.empty());
  // Frames fused now count; loading a map through the admin service forgets them again.
  for (int i = 0; i < 3; ++i) {
    auto frame = sequence.frameWithGroundTruth(i);
    ASSERT_TRUE(frame.ok()) << frame.error();
    publishFrame(h, frame.value().first);
    ASSERT_TRUE(h.waitPose("cam0", static_cast<uint64_t>(i), 20s)) << "no pose for frame " << i;
  }
  auto table_seen = restarted.objects(tables, 30s);
  ASSERT_TRUE(table_seen.ok() && table_seen.value().size() == 1u);
  EXPECT_EQ(table_seen.value()[0].frame_count, 3u);
  semfuse_srv_dds__Admin_Request_ load{};
  load.command = semfuse_srv_dds__Admin_Request_Constants_LOAD;
  const std::string map_path = map.string();
  load.path = const_cast<char*>(map_path.c_str());
  auto reloaded = h.admin().call(load, 30s);
  ASSERT_TRUE(reloaded.ok()) << reloaded.error();
  ASSERT_EQ(reloaded.value()->status, 0) << dds::replyMessage(*reloaded.value());
  auto table_reloaded = restarted.objects(tables, 30s);
  ASSERT_TRUE(table_reloaded.ok() && table_reloaded.value().size() == 1u);
  EXPECT_EQ(table_reloaded.value()[0].frame_count, 0u);
}

TEST_F(ServerEndToEnd, RejectsBadInputCountsItAndKeepsServing) {
  ServerHarness h(serverTestDomain());
  h.startServer(serverArgs(dir_ / "bad.vdb"));
  synthetic::SyntheticSequence sequence(sequenceConfig());
  auto both = sequence.frameWithGroundTruth(0);
  ASSERT_TRUE(both.ok());
  const Frame& good = both.value().first;
  publishFrame(h, good);
  ASSERT_TRUE(h.waitPose("cam0", 0, 20s));
  // The server's frames reader keeps only its last few samples (keep-last): write the next bad frame only once
  // the server has taken the previous one, so that each is rejected rather than overwritten.
  auto received = [&](uint64_t n) {
    return h.waitStatus([n](const auto& s) { return s.frames_received >= n; }, 20s)->frames_received >= n;
  };

  {  // depth payload shorter than width * height * 2
    auto encoded = wire::encodeFrame(good, {"16UC1"});
    ASSERT_TRUE(encoded.ok());
    encoded.value().msg().seq = 1;
    encoded.value().msg().depth._length -= 2;
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(received(2));
  }
  {  // NaN in the pose
    Frame nan_pose = good;
    nan_pose.seq = 2;
    auto encoded = wire::encodeFrame(nan_pose);
    ASSERT_TRUE(encoded.ok());
    encoded.value().msg().camera_to_world[3] = std::nan("");
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(received(3));
  }
  {  // unknown depth encoding
    Frame odd = good;
    odd.seq = 3;
    auto encoded = wire::encodeFrame(odd);
    ASSERT_TRUE(encoded.ok());
    encoded.value().msg().depth_encoding = const_cast<char*>("depth-as-gif");
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(received(4));
  }
  {  // JPEG colour cut short: libjpeg alone would decode it with grey where the data ends
    Frame cut = good;
    cut.seq = 4;
    wire::FrameEncoding jpeg;
    jpeg.color = "jpeg";
    auto encoded = wire::encodeFrame(cut, jpeg);
    ASSERT_TRUE(encoded.ok());
    encoded.value().msg().color._length /= 2;
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(received(5));
  }
  {  // segmentation for a camera that never sent a frame
    Segmentation stranger = both.value().second;
    stranger.camera_id = "nobody";
    publishSegmentation(h, stranger);
  }
  {  // label id outside the synthetic legend (1..8)
    Segmentation out_of_range = both.value().second;
    out_of_range.labels = out_of_range.labels.clone();
    out_of_range.labels.at<uint16_t>(5, 5) = 99;
    publishSegmentation(h, out_of_range);
  }
  {  // absurd raycast resolution
    auto request = raycastRequest(*good.camera_to_world, {100000, 100000, 500, 500, 50000, 50000},
                                  semfuse_srv_dds__Raycast_Request_Constants_LAYER_DEPTH);
    auto reply = h.raycast().call(request, 20s);
    ASSERT_TRUE(reply.ok()) << reply.error();
    EXPECT_EQ(reply.value()->status, semfuse_srv_dds__Status_Constants_TOO_LARGE);
    EXPECT_NE(std::string(dds::replyMessage(*reply.value())).find("100000x100000"), std::string::npos);
  }

  auto status = h.waitStatus(
      [](const auto& s) {
        return counterOf(s.rejected, "invalid_frame") >= 4 && counterOf(s.rejected, "unknown_camera") >= 1 &&
               counterOf(s.rejected, "label_out_of_legend") >= 1 && counterOf(s.rejected, "invalid_query") >= 1;
      },
      30s);
  ASSERT_NE(status.get(), nullptr);
  EXPECT_EQ(counterOf(status->rejected, "invalid_frame"), 4u);
  EXPECT_EQ(counterOf(status->rejected, "unknown_camera"), 1u);
  EXPECT_EQ(counterOf(status->rejected, "label_out_of_legend"), 1u);
  EXPECT_EQ(counterOf(status->rejected, "invalid_query"), 1u);
  EXPECT_EQ(status->frames_received, 5u);
  EXPECT_EQ(status->frames_integrated, 1u);
  EXPECT_EQ(counterOf(status->dropped, "sequence_gap"), 0u);
  // Each rejection left a precise message in the status.
  std::string errors;
  for (uint32_t i = 0; i < status->last_errors._length; ++i)
    errors += std::string(status->last_errors._buffer[i].message) + "\n";
  EXPECT_NE(errors.find("depth"), std::string::npos) << errors;
  EXPECT_NE(errors.find("99"), std::string::npos) << errors;
  EXPECT_NE(errors.find("nobody"), std::string::npos) << errors;
  EXPECT_NE(errors.find("Premature end of JPEG file"), std::string::npos) << errors;

  // Still serving: a good frame is integrated and a normal raycast answered.
  Frame next = good;
  next.seq = 5;
  publishFrame(h, next);
  ASSERT_TRUE(h.waitPose("cam0", 5, 20s));
  auto request =
      raycastRequest(*good.camera_to_world, good.intrinsics, semfuse_srv_dds__Raycast_Request_Constants_LAYER_DEPTH);
  auto reply = h.raycast().call(request, 20s);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.value()->status, 0) << dds::replyMessage(*reply.value());
  EXPECT_TRUE(h.serverRunning());
}

// A failed query reaches a user of the client library with the kind the server gave it, from
// the reply's status: the caller can tell a missing map from a bad request without its message.
TEST_F(ServerEndToEnd, ServiceFailuresReachTheClientLibraryWithTheirCodes) {
  ServerHarness h(serverTestDomain());
  h.startServer(serverArgs(dir_ / "codes.vdb"));
  client::MapClient map(h.participant());

  auto missing = map.load((dir_ / "no_such_map.vdb").string(), 30s);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.failure(), client::Failure::kServer) << missing.error();
  EXPECT_EQ(missing.errorCode(), ErrorCode::kNotFound) << missing.error();

  const PinholeIntrinsics no_focal{64, 48, 0.0, 50.0, 32.0, 24.0};
  auto invalid = map.raycast(Pose::Identity(), no_focal, client::kAllLayers, 30s);
  ASSERT_FALSE(invalid.ok());
  EXPECT_EQ(invalid.failure(), client::Failure::kServer) << invalid.error();
  EXPECT_EQ(invalid.errorCode(), ErrorCode::kInvalidArgument) << invalid.error();

  const PinholeIntrinsics huge{100000, 100000, 500.0, 500.0, 50000.0, 50000.0};
  auto too_large = map.raycast(Pose::Identity(), huge, client::kAllLayers, 30s);
  ASSERT_FALSE(too_large.ok());
  EXPECT_EQ(too_large.errorCode(), ErrorCode::kTooLarge) << too_large.error();
  EXPECT_TRUE(h.serverRunning());
}

// The top-5 label rules keep runners-up as 10-bit ids: a legend with a larger id is refused at
// startup (with the rule that would work) instead of losing those labels' evidence silently.
TEST_F(ServerEndToEnd, RefusesALegendBeyondTheTopFiveRulesIdRange) {
  const auto legend = dir_ / "wide.yaml";
  std::ofstream(legend) << "name: wide\nlabels:\n  - {id: 1, name: floor}\n  - {id: 2000, name: rare thing}\n";
  const auto log = dir_ / "server.log";
  const std::string command = std::string(SEMFUSE_SERVER_EXE) + " --domain-id 232 --legend " + legend.string() +
                              " --label-rule bayes > " + log.string() + " 2>&1 < /dev/null";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("keeps label ids up to 1023, but legend 'wide' has id 2000; use --label-rule evidence"),
            std::string::npos)
      << text;
}

}  // namespace
