// The distance field over DDS: semfuse-server with --esdf as a real process on loopback, fed the
// synthetic room with ground-truth labels; a MapClient asks every distance service, an
// OccupancyListener follows rt/semfuse/occupancy, and bad requests come back INVALID_ARGUMENT
// and are counted as invalid queries in the status.
#include <cmath>
#include <filesystem>
#include <limits>
#include <utility>

#include <gtest/gtest.h>

#include "semfuse/client/map_client.hpp"
#include "semfuse/client/occupancy_listener.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr int kRoomFrames = 30;
constexpr double kRoomVoxel = 0.05;

std::vector<std::string> esdfServerArgs() {
  return {"--legend",
          "synthetic",
          "--voxel-size",
          std::to_string(kRoomVoxel),
          "--truncation",
          std::to_string(2 * kRoomVoxel),
          "--autosave-period",
          "0",
          "--queue-per-camera",
          "64",
          "--max-queue-wait",
          "0",
          "--esdf",
          "--esdf.max-distance",
          "1.0",
          "--occupancy.rate",
          "5",
          "--occupancy.min-z",
          "0.15",
          "--occupancy.max-z",
          "0.6"};
}

}  // namespace

TEST(DistanceEndToEnd, ServesTheDistanceFieldAndPublishesTheOccupancyGrid) {
  ServerHarness h(serverTestDomain());
  h.startServer(esdfServerArgs());
  client::MapClient map(h.participant());
  client::OccupancyListener occupancy(h.participant());

  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);
  config.trajectory.frame_count = kRoomFrames;
  config.camera_id = "cam0";
  synthetic::SyntheticSequence sequence(config);
  for (int i = 0; i < kRoomFrames; ++i) {
    auto both = sequence.frameWithGroundTruth(i);
    ASSERT_TRUE(both.ok()) << both.error();
    auto frame = wire::encodeFrame(both.value().first);
    ASSERT_TRUE(frame.ok());
    ASSERT_TRUE(h.frames().write(frame.value().msg()).ok());
    ASSERT_TRUE(h.waitPose("cam0", static_cast<uint64_t>(i), 20s)) << "no pose for frame " << i;
    auto segmentation = wire::encodeSegmentation(both.value().second);
    ASSERT_TRUE(segmentation.ok());
    ASSERT_TRUE(h.segmentations().write(segmentation.value().msg()).ok());
  }
  // The field follows the map on its own thread (at query priority, slowest under load): wait
  // until the map has taken every frame and label and the field has applied all of it.
  const auto settled = h.waitStatus(
      [](const auto& s) {
        return s.segmentations_integrated == kRoomFrames && s.queued_frames == 0 && s.pending_segmentations == 0 &&
               s.map_revision > 0 && s.distance_field_revision == s.map_revision;
      },
      60s);
  ASSERT_EQ(settled->segmentations_integrated, static_cast<uint64_t>(kRoomFrames));
  ASSERT_GT(settled->map_revision, 0u);
  ASSERT_EQ(settled->distance_field_revision, settled->map_revision) << "the field never caught up with the map";

  const Eigen::Vector3d above_table(0.0, 0.3, 1.0);
  const Eigen::Vector3d over_table(0.2, 0.1, 1.25);
  auto distances = map.distances({above_table}, 10s);
  ASSERT_TRUE(distances) << distances.error();
  ASSERT_TRUE(distances.value()[0].known);
  EXPECT_NEAR(distances.value()[0].distance, 0.25, 1.5 * kRoomVoxel);
  EXPECT_GT(distances.value()[0].gradient.z(), 0.8f);
  // Thousands of points in one call; above the ceiling nobody looked.
  std::vector<Eigen::Vector3d> many(5000, above_table);
  many.back() = {0.0, 0.0, 9.0};
  auto batch = map.distances(many, 10s);
  ASSERT_TRUE(batch) << batch.error();
  ASSERT_EQ(batch.value().size(), many.size());
  EXPECT_FLOAT_EQ(batch.value()[4321].distance, batch.value()[0].distance);
  EXPECT_FALSE(batch.value().back().known);

  client::OccupancySliceRequest slice;
  slice.z_min = 0.15;
  slice.z_max = 0.6;
  slice.use_bounds = true;
  slice.min = {-2.5, -2.0};
  slice.max = {2.5, 2.0};
  auto grid = map.occupancySlice(slice, 10s);
  ASSERT_TRUE(grid) << grid.error();
  EXPECT_EQ(grid.value().width, 101u);
  EXPECT_EQ(grid.value().height, 81u);
  EXPECT_EQ(grid.value().cells[40 * 101 + 0], kOccupancyOccupied);  // the -x wall at y = 0
  EXPECT_EQ(grid.value().cells[30 * 101 + 18], kOccupancyFree);     // (-1.6, -0.5)

  auto table = map.semanticDistances({synthetic::labels::kTable}, {over_table}, 10s);
  ASSERT_TRUE(table) << table.error();
  ASSERT_TRUE(table.value()[0].found);
  EXPECT_NEAR(table.value()[0].distance, 0.5, 1.5 * kRoomVoxel);
  EXPECT_LT(table.value()[0].direction.z(), -0.9f);
  auto table_slice = map.semanticSlice({{synthetic::labels::kTable}, 1.25, {-1.0, -1.0}, {1.0, 1.0}, 0.1}, 10s);
  ASSERT_TRUE(table_slice) << table_slice.error();
  EXPECT_EQ(table_slice.value().distance.size(), cv::Size(20, 20));
  EXPECT_NEAR(table_slice.value().distance.at<float>(11, 12), 0.5, 1.5 * kRoomVoxel);

  auto segments =
      map.checkSegments({{{0.2, -0.6, 1.0}, {0.2, 0.8, 0.5}}, {{-1.6, -1.0, 1.0}, {-1.6, 0.5, 1.0}}}, 0.0, 10s);
  ASSERT_TRUE(segments) << segments.error();
  EXPECT_EQ(segments.value()[0].status, client::SegmentStatus::kCollision);
  EXPECT_EQ(segments.value()[1].status, client::SegmentStatus::kFree);

  // The occupancy topic: the configured band over the whole observed extent, once the publisher
  // has sliced a field with every frame in it. The field follows the map on its own thread and
  // answers queries between the slices of an update, so the queries above do not wait for the
  // last update to end: the grid on the topic may still be one from before it.
  auto published = occupancy.waitForGrid(10s);
  for (int tries = 0; tries < 100 && published && published->width * kRoomVoxel < 5.0; ++tries) {
    std::this_thread::sleep_for(100ms);
    published = occupancy.latest();
  }
  ASSERT_TRUE(published.has_value());
  EXPECT_EQ(published->frame_id, "map");
  EXPECT_FLOAT_EQ(static_cast<float>(published->resolution), static_cast<float>(kRoomVoxel));  // float32 on the wire
  EXPECT_NEAR(published->z, 0.375, 1e-9);
  EXPECT_GE(published->width * kRoomVoxel, 5.0);
  EXPECT_GE(published->height * kRoomVoxel, 4.0);
  EXPECT_EQ(published->cells.size(), static_cast<std::size_t>(published->width) * published->height);
  EXPECT_EQ(occupancy.rejected(), 0u);

  // Bad requests: refused with INVALID_ARGUMENT and a reason, and counted.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto before = h.waitStatus([](const auto&) { return true; }, 1s);
  const uint64_t invalid_before = counterOf(before->rejected, "invalid_query");
  auto nan_point = map.distances({{0.0, nan, 1.0}}, 10s);
  ASSERT_FALSE(nan_point);
  EXPECT_EQ(nan_point.failure(), client::Failure::kServer);
  EXPECT_EQ(nan_point.errorCode(), ErrorCode::kInvalidArgument);
  EXPECT_NE(nan_point.error().find("not finite"), std::string::npos) << nan_point.error();
  auto no_labels = map.semanticDistances({}, {{0.0, 0.0, 1.0}}, 10s);
  EXPECT_EQ(no_labels.errorCode(), ErrorCode::kInvalidArgument);
  client::OccupancySliceRequest inverted;
  inverted.z_min = 1.0;
  inverted.z_max = 0.2;
  EXPECT_EQ(map.occupancySlice(inverted, 10s).errorCode(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(map.semanticSlice({{synthetic::labels::kTable}, 1.0, {0, 0}, {0, 0}, 0.1}, 10s).errorCode(),
            ErrorCode::kInvalidArgument);
  const auto after =
      h.waitStatus([&](const auto& s) { return counterOf(s.rejected, "invalid_query") >= invalid_before + 4; }, 10s);
  EXPECT_EQ(counterOf(after->rejected, "invalid_query"), invalid_before + 4);

  EXPECT_EQ(h.stopServer(), 0);
}

TEST(DistanceEndToEnd, WithoutEsdfTheServicesSaySo) {
  // A domain of its own (the next id may be another test process's).
  ServerHarness h(static_cast<dds_domainid_t>(reserveAnotherTestDomain()));
  h.startServer({"--legend", "synthetic", "--autosave-period", "0"});
  client::MapClient map(h.participant());
  auto reply = map.distances({{0.0, 0.0, 1.0}}, 10s);
  ASSERT_FALSE(reply);
  EXPECT_EQ(reply.errorCode(), ErrorCode::kUnavailable);
  EXPECT_NE(reply.error().find("--esdf"), std::string::npos) << reply.error();
  EXPECT_EQ(h.stopServer(), 0);
}
