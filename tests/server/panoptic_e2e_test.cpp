// Panoptic instances over DDS: semfuse-server as a real process fed two boxes of one class that
// touch, flush, along a face, so that their surface is that of one long box. Sent with their
// instance maps they are two objects, with labels only one; the map file keeps the instances,
// a restarted server still answers two; an instance map the server cannot use is refused, counted
// and the run goes on.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "semfuse/client/map_client.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"
#include "semfuse/volume/map_file.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace panoptic_e2e {  // named: the unity build puts this file beside other e2e tests

constexpr int kOrbitFrames = 24;
constexpr double kBoxVoxel = 0.02;
constexpr double kHalf = 0.15;  // each box is a 0.3 m cube; they meet at x = 0

synthetic::LabeledScene twoTouchingBoxes() {
  synthetic::LabeledScene scene;
  scene.add({"floor", synthetic::OrientedBox{{0, 0, -0.1}, {2.0, 2.0, 0.1}, Eigen::Matrix3d::Identity()},
             synthetic::labels::kFloor});
  for (const double x : {-kHalf, kHalf})
    scene.add({"box", synthetic::OrientedBox{{x, 0, kHalf}, {kHalf, kHalf, kHalf}, Eigen::Matrix3d::Identity()},
               synthetic::labels::kBox});
  return scene;
}

// An orbit of the pair, looking down at it a little, every side seen.
Pose orbitPose(int i) {
  const double angle = 2.0 * M_PI * i / kOrbitFrames;
  return synthetic::lookAt({1.1 * std::cos(angle), 1.1 * std::sin(angle), 0.8}, {0.0, 0.0, 0.12});
}

std::vector<std::string> boxServerArgs(const std::filesystem::path& map) {
  return {"--legend",
          "synthetic",
          "--voxel-size",
          std::to_string(kBoxVoxel),
          "--truncation",
          "0.08",
          "--map",
          map.string(),
          "--autosave-period",
          "0",
          "--queue-per-camera",
          "64",
          "--max-queue-wait",
          "0"};
}

// Frame `seq` of camera cam0 as the renderer saw it (with colour when `color`).
Frame frameOf(const synthetic::RenderedView& view, int seq, bool color) {
  Frame frame;
  frame.camera_id = "cam0";
  frame.seq = static_cast<uint64_t>(seq);
  frame.intrinsics = view.intrinsics;
  frame.depth = view.depth;
  if (color) frame.color = view.color;
  frame.camera_to_world = view.camera_to_world;
  return frame;
}

// Streams the orbit with its segmentations (with or without instances) and waits until the map
// has all of them.
void streamBoxes(ServerHarness& h, bool instances) {
  const synthetic::LabeledScene scene = twoTouchingBoxes();
  const PinholeIntrinsics k = PinholeIntrinsics{640, 480, 525.0, 525.0, 319.5, 239.5}.scaled(0.5);
  for (int i = 0; i < kOrbitFrames; ++i) {
    auto view = synthetic::renderView(scene, k, orbitPose(i));
    ASSERT_TRUE(view.ok()) << view.error();
    const Frame frame = frameOf(view.value(), i, true);
    auto encoded = wire::encodeFrame(frame);
    ASSERT_TRUE(encoded.ok()) << encoded.error();
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(h.waitPose("cam0", frame.seq, 20s)) << "no pose for frame " << i;
    Segmentation segmentation;
    segmentation.camera_id = "cam0";
    segmentation.frame_seq = frame.seq;
    segmentation.segmenter_id = instances ? "panoptic" : "semantic";
    segmentation.labels = view.value().labels;
    // A segmenter's ids are its own: give each frame other ones than the scene's.
    if (instances) segmentation.instances = view.value().instances * 3 + static_cast<double>(i % 5);
    if (instances) segmentation.instances.setTo(0, view.value().instances == 0);
    auto seg = wire::encodeSegmentation(segmentation);
    ASSERT_TRUE(seg.ok()) << seg.error();
    ASSERT_TRUE(h.segmentations().write(seg.value().msg()).ok());
  }
  const auto status = h.waitStatus(
      [](const auto& s) { return s.segmentations_integrated == kOrbitFrames && s.pending_segmentations == 0; }, 60s);
  ASSERT_EQ(status->segmentations_integrated, static_cast<uint64_t>(kOrbitFrames));
  ASSERT_EQ(counterTotal(status->rejected), 0u);
}

std::vector<ObjectInstance> boxes(client::MapClient& map) {
  ObjectsRequest request;
  request.label = synthetic::labels::kBox;
  auto objects = map.objects(request, 30s);
  EXPECT_TRUE(objects.ok()) << objects.error();
  return objects.ok() ? objects.value() : std::vector<ObjectInstance>{};
}

// The two objects are the two cubes: one on each side of x = 0, each about a cube's size.
void expectTheTwoCubes(std::vector<ObjectInstance> objects) {
  ASSERT_EQ(objects.size(), 2u);
  std::sort(objects.begin(), objects.end(),
            [](const ObjectInstance& a, const ObjectInstance& b) { return a.centroid.x() < b.centroid.x(); });
  EXPECT_NEAR(objects[0].centroid.x(), -kHalf, 0.05);
  EXPECT_NEAR(objects[1].centroid.x(), kHalf, 0.05);
  for (const ObjectInstance& o : objects) {
    EXPECT_NEAR(o.bbox_max.x() - o.bbox_min.x(), 2 * kHalf, 3 * kBoxVoxel) << o.id;
    EXPECT_NEAR(o.bbox_max.y() - o.bbox_min.y(), 2 * kHalf, 3 * kBoxVoxel) << o.id;
  }
}

}  // namespace panoptic_e2e
using namespace panoptic_e2e;

TEST(PanopticEndToEnd, TwoTouchingBoxesAreTwoObjectsWithInstancesAndOneWithout) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "panoptic_boxes";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);

  {
    ServerHarness h(serverTestDomain());
    h.startServer(boxServerArgs(dir / "semantic.vdb"));
    streamBoxes(h, false);
    client::MapClient map(h.participant());
    const std::vector<ObjectInstance> one = boxes(map);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_NEAR(one[0].bbox_max.x() - one[0].bbox_min.x(), 4 * kHalf,
                4 * kBoxVoxel);  // surface voxels reach past the faces
    EXPECT_EQ(h.stopServer(), 0);
  }

  ServerHarness h(static_cast<dds_domainid_t>(reserveAnotherTestDomain()));
  const std::filesystem::path map_file = dir / "panoptic.vdb";
  h.startServer(boxServerArgs(map_file));
  streamBoxes(h, true);
  client::MapClient map(h.participant());
  expectTheTwoCubes(boxes(map));

  // The map file keeps the instance evidence, and a server resumed from it answers the same.
  h.saveMap();
  if (::testing::Test::HasFatalFailure()) return;
  auto loaded = volume::loadMap(map_file);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  ASSERT_NE(loaded.value().volume.instanceGrid(), nullptr);
  EXPECT_GT(loaded.value().volume.instanceGrid()->activeVoxelCount(), 1000u);
  EXPECT_GE(loaded.value().volume.nextInstanceId(), 3u);  // the floor and both cubes
  EXPECT_EQ(h.stopServer(), 0);
  h.startServer(boxServerArgs(map_file));
  client::MapClient resumed(h.participant());
  expectTheTwoCubes(boxes(resumed));
  EXPECT_EQ(h.stopServer(), 0);
}

TEST(PanopticEndToEnd, AnInstanceMapTheServerCannotUseIsRefusedCountedAndTheRunGoesOn) {
  ServerHarness h(serverTestDomain());
  h.startServer(
      {"--legend", "synthetic", "--autosave-period", "0", "--queue-per-camera", "64", "--max-queue-wait", "0"});
  const synthetic::LabeledScene scene = twoTouchingBoxes();
  const PinholeIntrinsics k = PinholeIntrinsics{640, 480, 525.0, 525.0, 319.5, 239.5}.scaled(0.25);
  for (int i = 0; i < 3; ++i) {
    auto view = synthetic::renderView(scene, k, orbitPose(i));
    ASSERT_TRUE(view.ok());
    const Frame frame = frameOf(view.value(), i, false);
    auto encoded = wire::encodeFrame(frame);
    ASSERT_TRUE(encoded.ok());
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(h.waitPose("cam0", frame.seq, 20s));
    Segmentation segmentation;
    segmentation.camera_id = "cam0";
    segmentation.frame_seq = frame.seq;
    segmentation.labels = view.value().labels;
    segmentation.instances = view.value().instances;
    auto seg = wire::encodeSegmentation(segmentation);
    ASSERT_TRUE(seg.ok());
    auto& msg = seg.value().msg();
    if (i == 0) msg.instances._length -= 7;  // not the labels' size
    if (i == 1)
      for (uint32_t p = 0; p < msg.labels._length; ++p) msg.labels._buffer[p] = 0;  // instances, no labels
    ASSERT_TRUE(h.segmentations().write(msg).ok());
  }
  const auto status = h.waitStatus(
      [](const auto& s) {
        return counterOf(s.rejected, "invalid_segmentation") >= 2 && s.segmentations_integrated >= 1 &&
               s.frames_integrated >= 3;
      },
      30s);
  EXPECT_EQ(counterOf(status->rejected, "invalid_segmentation"), 2u);
  EXPECT_EQ(status->segmentations_integrated, 1u);
  EXPECT_EQ(status->frames_integrated, 3u);
  std::vector<std::string> errors;
  for (uint32_t e = 0; e < status->last_errors._length; ++e)
    errors.emplace_back(status->last_errors._buffer[e].message);
  EXPECT_TRUE(std::any_of(errors.begin(), errors.end(), [](const std::string& m) {
    return m.find("instances: ") != std::string::npos && m.find("expected") != std::string::npos;
  }));
  EXPECT_TRUE(std::any_of(errors.begin(), errors.end(),
                          [](const std::string& m) { return m.find("none has a label") != std::string::npos; }));
  EXPECT_EQ(h.stopServer(), 0);
}
