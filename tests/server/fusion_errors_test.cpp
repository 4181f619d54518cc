// The server core tells failures apart by their error codes, never by their messages: which
// reason a rejected frame is counted under, and the codes an admin load or a late task fails with
// (the status the admin service replies with). Frames passed over in the queue are counted too.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "eventually.hpp"
#include "fusion_loop.hpp"
#include "mapper.hpp"
#include "semfuse/wire/reply_status.hpp"
#include "server_state.hpp"
#include "srv.h"
#include "wall_scene.hpp"

using namespace semfuse;
using namespace semfuse::server;
using namespace semfuse::server::wall_scene;
using semfuse::testing::eventually;
using namespace std::chrono_literals;

namespace {

void waitIdle(const FusionLoop& loop) {
  ASSERT_TRUE(eventually([&] { return loop.idle(); }));
}

}  // namespace

TEST(FusionErrors, FramesPassedOverForANewerOneAreCountedAsStale) {
  Mapper mapper(wallMapOptions());
  // Backlog time zero: a camera behind at a single turn has its newest fused.
  FrameQueue frames(4, 20ms, 0ms);
  ServerState state;
  FusionLoop loop(mapper, frames, state, FusionLimits{}, nullptr);
  for (uint64_t seq = 1; seq <= 3; ++seq) ASSERT_FALSE(frames.push(wallFrame("a", seq, true)));
  std::this_thread::sleep_for(50ms);  // the fusion thread fell behind
  ASSERT_FALSE(frames.push(wallFrame("a", 4, true)));
  loop.start();
  waitIdle(loop);
  loop.stop();
  // The newest frame is fused, the three that waited too long are dropped and counted.
  EXPECT_EQ(state.frames_integrated.load(), 1u);
  EXPECT_EQ(state.dropped.get(reason::kQueueStale, "a"), 3u);
  EXPECT_EQ(state.cameras().at("a").frames_integrated, 1u);
}

TEST(FusionErrors, MalformedFramesAreIntegrationFailuresAnUnplacedCameraIsLostNotRejected) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(4);
  ServerState state;
  FusionLoop loop(mapper, frames, state, FusionLimits{}, nullptr);
  loop.start();
  ASSERT_FALSE(frames.push(wallFrame("a", 1, true)));
  waitIdle(loop);
  // A second camera without poses that sees only a wall: no keyframe alignment can place it (a
  // plane leaves the pose along it free), so its frame is lost, counted, and not integrated.
  ASSERT_FALSE(frames.push(wallFrame("b", 1, false)));
  // A frame whose depth does not match its intrinsics is refused as malformed.
  Frame mismatched = wallFrame("c", 1, true);
  mismatched.depth = cv::Mat(kWallHeight / 2, kWallWidth / 2, CV_32FC1, cv::Scalar(1.5f));
  ASSERT_FALSE(frames.push(mismatched));
  waitIdle(loop);
  loop.stop();

  EXPECT_EQ(state.frames_integrated.load(), 1u);
  EXPECT_EQ(state.rejected.get(reason::kIntegrationFailed, "b"), 0u);
  EXPECT_EQ(state.dropped.get(reason::kTrackingLost, "b"), 1u);
  EXPECT_EQ(state.rejected.get(reason::kIntegrationFailed, "c"), 1u);
  const auto cameras = state.cameras();
  ASSERT_EQ(cameras.count("b"), 1u);
  EXPECT_EQ(cameras.at("b").frames_lost, 1u);
  EXPECT_EQ(cameras.at("b").frames_since_lost, 1u);
  EXPECT_EQ(cameras.at("b").relocalisations, 0u);
  EXPECT_FALSE(cameras.at("b").lost_reason.empty());
}

// A segmentation that waits for a frame the queue then drops is counted as soon as a later frame
// of its camera is fused, not left to be evicted (pending_full) or to time out.
TEST(FusionErrors, ASegmentationOfADroppedFrameIsCountedWhenALaterFrameIsFused) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(1);
  ServerState state;
  FusionLimits limits;
  limits.pending_timeout_s = 60.0;
  // Every frame integrated: a tracking thread then waits, holding its camera, while 2 frames wait
  // for the fusion thread, which lets the test fill the frame queue however the threads are
  // scheduled (a tracking thread that is free takes a queued frame at once).
  limits.integrate_every_frame = true;
  FusionLoop loop(mapper, frames, state, limits, nullptr);
  loop.start();
  ASSERT_FALSE(frames.push(wallFrame("a", 1, true)));
  waitIdle(loop);
  // Segmentations of frames 5 and 7 arrive first and wait, while the fusion thread is held by a task.
  std::promise<void> started, release;
  auto held = std::async(std::launch::async, [&] {
    return loop.runOnFusionThread(
        [&] {
          started.set_value();
          release.get_future().wait();
          return Status::Ok();
        },
        60s);
  });
  started.get_future().wait();
  for (uint64_t seq : {5u, 7u}) {
    Segmentation segmentation;
    segmentation.camera_id = "a";
    segmentation.segmenter_id = "s";
    segmentation.frame_seq = seq;
    segmentation.labels = cv::Mat(kWallHeight, kWallWidth, CV_16UC1, cv::Scalar(1));
    loop.submitSegmentation(std::move(segmentation));
  }
  // Frames 2 and 3 wait for integration; the tracking thread holds frame 4 until there is room.
  for (uint64_t seq : {2u, 3u, 4u}) {
    ASSERT_FALSE(frames.push(wallFrame("a", seq, true)));
    ASSERT_TRUE(eventually([&] { return frames.size() == 0; })) << "frame " << seq << " was not taken";
  }
  ASSERT_TRUE(eventually([&] { return loop.framesAwaitingIntegration() == 2 && frames.held() == 1; }));
  // Frame 5 is queued behind it, and dropped at the full queue for frame 6.
  ASSERT_FALSE(frames.push(wallFrame("a", 5, true)));
  const auto evicted = frames.push(wallFrame("a", 6, true));
  ASSERT_TRUE(evicted);
  EXPECT_EQ(evicted->seq, 5u);
  release.set_value();
  ASSERT_TRUE(held.get().ok());
  waitIdle(loop);
  EXPECT_EQ(state.frames_integrated.load(), 5u);                 // 1, 2, 3, 4 and 6
  EXPECT_EQ(state.dropped.get(reason::kFrameDropped, "a"), 1u);  // the one of frame 5
  EXPECT_EQ(loop.pendingSegmentations(), 1u);                    // frame 7's still waits
  ASSERT_FALSE(frames.push(wallFrame("a", 7, true)));
  waitIdle(loop);
  loop.stop();
  EXPECT_EQ(loop.pendingSegmentations(), 0u);
  EXPECT_EQ(state.segmentations_integrated.load(), 1u);
  EXPECT_EQ(state.dropped.get(reason::kFrameDropped, "a"), 1u);
  EXPECT_EQ(state.dropped.get(reason::kPendingFull, "a"), 0u);
  EXPECT_EQ(state.dropped.get(reason::kSegmentationTimeout, "a"), 0u);
}

TEST(FusionErrors, MapperNeverPlacesASecondPoselessCameraAtAGuess) {
  Mapper mapper(wallMapOptions());
  // The first camera of an empty map defines the world frame: no pose needed.
  ASSERT_TRUE(mapper.integrateFrame(wallFrame("a", 1, false)).ok());
  auto second = mapper.integrateFrame(wallFrame("b", 1, false));
  ASSERT_TRUE(second.ok()) << second.error();
  EXPECT_FALSE(second.value().integrated);
  EXPECT_EQ(second.value().pose_state, PoseState::kLost);
  EXPECT_NE(second.value().lost_reason, "");
  EXPECT_EQ(second.value().frames_since_lost, 1u);
}

TEST(FusionErrors, AdminLoadFailuresCarryTheCodeTheServiceRepliesWith) {
  const auto folder = std::filesystem::temp_directory_path() / ("semfuse_fusion_errors_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  Mapper mapper(wallMapOptions(0.02));

  Status missing = mapper.load(folder / "no_such_map.vdb");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.errorCode(), ErrorCode::kNotFound) << missing.error();
  EXPECT_EQ(wire::replyStatusOf(missing.errorCode()), semfuse_srv_dds__Status_Constants_NOT_FOUND);

  // A map of another voxel size is refused without touching the server's map.
  Mapper other(wallMapOptions(0.04));
  ASSERT_TRUE(other.integrateFrame(wallFrame("a", 1, true)).ok());
  ASSERT_TRUE(other.save(folder / "coarse.vdb").ok());
  Status incompatible = mapper.load(folder / "coarse.vdb");
  ASSERT_FALSE(incompatible.ok());
  EXPECT_EQ(incompatible.errorCode(), ErrorCode::kInvalidArgument) << incompatible.error();

  // Bytes that are not a map.
  { std::ofstream(folder / "garbage.vdb") << "not a map"; }
  Status garbage = mapper.load(folder / "garbage.vdb");
  ASSERT_FALSE(garbage.ok());
  EXPECT_EQ(garbage.errorCode(), ErrorCode::kInvalidArgument) << garbage.error();
  EXPECT_EQ(mapper.size().frames_integrated, 0u);
  std::filesystem::remove_all(folder);
}

TEST(FusionErrors, ATaskTheFusionThreadDoesNotRunInTimeIsUnavailable) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(4);
  ServerState state;
  FusionLoop loop(mapper, frames, state, FusionLimits{}, nullptr);  // not started: nothing runs tasks
  Status late = loop.runOnFusionThread([] { return Status::Ok(); }, 20ms);
  ASSERT_FALSE(late.ok());
  EXPECT_EQ(late.errorCode(), ErrorCode::kUnavailable) << late.error();
  EXPECT_EQ(wire::replyStatusOf(late.errorCode()), semfuse_srv_dds__Status_Constants_UNAVAILABLE);
}
