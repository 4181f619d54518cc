// The frame pipeline: tracking threads pose every frame, in order, whatever the fusion thread is
// doing; the fusion thread integrates the newest posed frame of each camera in turn and keeps the
// others (skipped) in the history, where their segmentations are still fused. Every frame ends
// posed (integrated or skipped), lost or counted. The fusion thread is held by a task to make
// integration fall behind: the tests wait for conditions, never for the clock.
#include <atomic>
#include <future>
#include <mutex>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "eventually.hpp"
#include "fusion_loop.hpp"
#include "integration_queue.hpp"
#include "mapper.hpp"
#include "server_state.hpp"
#include "wall_scene.hpp"

using namespace semfuse;
using namespace semfuse::server;
using namespace semfuse::server::wall_scene;
using semfuse::testing::eventually;
using namespace std::chrono_literals;

namespace {

Segmentation pipelineLabels(const std::string& camera, uint64_t seq) {
  Segmentation segmentation;
  segmentation.camera_id = camera;
  segmentation.segmenter_id = "s";
  segmentation.frame_seq = seq;
  segmentation.labels = cv::Mat(kWallHeight, kWallWidth, CV_16UC1, cv::Scalar(1));
  return segmentation;
}

// Poses as the tracking threads hand them out, in the order they came.
struct PoseLog {
  std::mutex mutex;
  std::vector<std::pair<std::string, uint64_t>> poses;
  std::atomic<size_t> count{0};
  FusionLoop::PoseCallback callback() {
    return [this](const PosedFrame& frame) {
      std::lock_guard lock(mutex);
      poses.emplace_back(frame.frame.camera_id, frame.frame.seq);
      ++count;
    };
  }
};

// Holds the fusion thread in a task until released.
class HeldFusion {
 public:
  explicit HeldFusion(FusionLoop& loop) {
    result_ = std::async(std::launch::async, [this, &loop] {
      return loop.runOnFusionThread(
          [this] {
            started_.set_value();
            release_.get_future().wait();
            return Status::Ok();
          },
          60s);
    });
    started_.get_future().wait();
  }
  bool release() {
    release_.set_value();
    return result_.get().ok();
  }

 private:
  std::promise<void> started_, release_;
  std::future<Status> result_;
};

PosedFrame queued(const std::string& camera, uint64_t seq) {
  PosedFrame frame;
  frame.frame.camera_id = camera;
  frame.frame.seq = seq;
  return frame;
}

}  // namespace

TEST(IntegrationQueue, NewestFirstTakesACamerasFramesTogetherAndServesCamerasInTurn) {
  IntegrationQueue queue(false, 2);
  for (uint64_t seq = 1; seq <= 3; ++seq) queue.push(queued("a", seq));
  queue.push(queued("b", 1));
  std::set<std::string> served;
  for (int turn = 0; turn < 2; ++turn) {
    const std::vector<PosedFrame> frames = queue.take(0ms);
    ASSERT_FALSE(frames.empty());
    served.insert(frames.front().frame.camera_id);
    if (frames.front().frame.camera_id == "a") {
      ASSERT_EQ(frames.size(), 3u);  // oldest first: the fusion thread integrates the last
      EXPECT_EQ(frames.front().frame.seq, 1u);
      EXPECT_EQ(frames.back().frame.seq, 3u);
    }
    queue.finished();
  }
  EXPECT_EQ(served, (std::set<std::string>{"a", "b"}));
  EXPECT_TRUE(queue.idle());
  EXPECT_TRUE(queue.take(0ms).empty());
}

TEST(IntegrationQueue, EveryFrameHandsOutOneAtATimeAndHoldsTrackingBackAtItsCapacity) {
  IntegrationQueue queue(true, 2);
  queue.push(queued("a", 1));
  queue.push(queued("a", 2));
  std::atomic<bool> third_in{false};
  std::thread tracker([&] {
    queue.push(queued("a", 3));  // waits: the camera has two frames waiting
    third_in = true;
  });
  std::this_thread::sleep_for(20ms);
  EXPECT_FALSE(third_in.load());
  const std::vector<PosedFrame> first = queue.take(0ms);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first.front().frame.seq, 1u);
  queue.finished();
  tracker.join();
  EXPECT_TRUE(third_in.load());
  EXPECT_EQ(queue.take(0ms).front().frame.seq, 2u);
  queue.finished();
  EXPECT_EQ(queue.take(0ms).front().frame.seq, 3u);
  queue.finished();
}

TEST(FramePipeline, EveryFrameIsPosedInOrderWhileIntegrationIsHeldAndTheRestAreSkippedNotDropped) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(16);
  ServerState state;
  PoseLog log;
  FusionLimits limits;
  limits.tracking_threads = 2;
  FusionLoop loop(mapper, frames, state, limits, log.callback());
  loop.start();
  constexpr uint64_t kFrames = 10;
  {
    HeldFusion held(loop);
    for (uint64_t seq = 1; seq <= kFrames; ++seq) {
      ASSERT_FALSE(frames.push(wallFrame("a", seq, true)));
      // Labels of every other frame, waiting for their frame.
      if (seq % 2 == 0) loop.submitSegmentation(pipelineLabels("a", seq));
    }
    // Every pose goes out although nothing is integrated.
    ASSERT_TRUE(eventually([&] { return log.count.load() == kFrames && loop.framesAwaitingIntegration() == kFrames; }));
    EXPECT_EQ(state.frames_integrated.load(), 0u);
    ASSERT_TRUE(held.release());
  }
  ASSERT_TRUE(eventually([&] { return loop.idle(); }));
  loop.stop();

  {
    std::lock_guard lock(log.mutex);
    for (uint64_t k = 0; k < kFrames; ++k) EXPECT_EQ(log.poses[k], (std::pair<std::string, uint64_t>{"a", k + 1}));
  }
  EXPECT_EQ(state.frames_posed.load(), kFrames);
  // The fusion thread took the ten at once: the newest integrated, the nine before it skipped.
  EXPECT_EQ(state.frames_integrated.load(), 1u);
  EXPECT_EQ(state.frames_skipped.load(), kFrames - 1);
  const CameraActivity camera = state.cameras().at("a");
  EXPECT_EQ(camera.frames_posed, kFrames);
  EXPECT_EQ(camera.frames_integrated + camera.frames_skipped, kFrames);
  // The segmentations of skipped frames were fused with their own frame's depth and pose.
  EXPECT_EQ(state.segmentations_integrated.load(), kFrames / 2);
  EXPECT_EQ(state.dropped.snapshot().size(), 0u);
}

TEST(FramePipeline, ASegmentationOfASkippedFrameThatComesLaterIsStillFused) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(16);
  ServerState state;
  PoseLog log;
  FusionLoop loop(mapper, frames, state, FusionLimits{}, log.callback());
  loop.start();
  {
    HeldFusion held(loop);
    for (uint64_t seq = 1; seq <= 3; ++seq) ASSERT_FALSE(frames.push(wallFrame("a", seq, true)));
    ASSERT_TRUE(eventually([&] { return loop.framesAwaitingIntegration() == 3; }));
    ASSERT_TRUE(held.release());
  }
  ASSERT_TRUE(eventually([&] { return loop.idle(); }));
  ASSERT_EQ(state.frames_skipped.load(), 2u);
  loop.submitSegmentation(pipelineLabels("a", 1));  // frame 1 was skipped
  ASSERT_TRUE(eventually([&] { return state.segmentations_integrated.load() == 1; }));
  loop.stop();
  EXPECT_EQ(state.rejected.snapshot().size(), 0u);
}

TEST(FramePipeline, LabelPassesBeyondTheQueueAreCountedAsBehind) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(32);
  ServerState state;
  PoseLog log;
  FusionLoop loop(mapper, frames, state, FusionLimits{}, log.callback());
  loop.start();
  constexpr uint64_t kFrames = 20;
  {
    // Twenty frames and their labels reach the fusion thread in one turn: the newest frame is
    // integrated with its labels, the other nineteen are skipped and their labels queue.
    HeldFusion held(loop);
    for (uint64_t seq = 1; seq <= kFrames; ++seq) {
      ASSERT_FALSE(frames.push(wallFrame("a", seq, true)));
      loop.submitSegmentation(pipelineLabels("a", seq));
    }
    ASSERT_TRUE(eventually([&] { return loop.framesAwaitingIntegration() == kFrames; }));
    ASSERT_TRUE(held.release());
  }
  ASSERT_TRUE(eventually([&] { return loop.idle(); }));
  loop.stop();
  EXPECT_EQ(state.frames_integrated.load(), 1u);
  EXPECT_EQ(state.segmentations_integrated.load(), 1u + 16u);
  const auto dropped = state.dropped.snapshot();
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped.front().reason, reason::kLabelsBehind);
  EXPECT_EQ(dropped.front().count, kFrames - 1 - 16);
  EXPECT_EQ(loop.pendingSegmentations(), 0u);
}

TEST(FramePipeline, WithEveryFrameIntegratedNoneIsSkipped) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(16);
  ServerState state;
  PoseLog log;
  FusionLimits limits;
  limits.integrate_every_frame = true;
  FusionLoop loop(mapper, frames, state, limits, log.callback());
  loop.start();
  constexpr uint64_t kFrames = 8;
  {
    HeldFusion held(loop);
    for (uint64_t seq = 1; seq <= kFrames; ++seq) ASSERT_FALSE(frames.push(wallFrame("a", seq, true)));
    // Tracking runs ahead of the held integration by a bounded number of frames.
    ASSERT_TRUE(eventually([&] { return loop.framesAwaitingIntegration() == 2; }));
    ASSERT_TRUE(held.release());
  }
  ASSERT_TRUE(eventually([&] { return loop.idle() && state.frames_integrated.load() == kFrames; }));
  loop.stop();
  EXPECT_EQ(state.frames_skipped.load(), 0u);
  EXPECT_EQ(log.count.load(), kFrames);
}

TEST(FramePipeline, APosedFrameOfAMapReplacedSinceIsCountedNotIntegrated) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(16);
  ServerState state;
  PoseLog log;
  FusionLoop loop(mapper, frames, state, FusionLimits{}, log.callback());
  loop.start();
  std::promise<void> started, release;
  auto reset = std::async(std::launch::async, [&] {
    return loop.runOnFusionThread(
        [&] {
          started.set_value();
          release.get_future().wait();  // the frame is tracked meanwhile, against the old map
          mapper.reset();
          return Status::Ok();
        },
        60s);
  });
  started.get_future().wait();
  ASSERT_FALSE(frames.push(wallFrame("a", 1, true)));
  ASSERT_TRUE(eventually([&] { return log.count.load() == 1; }));
  release.set_value();
  ASSERT_TRUE(reset.get().ok());
  ASSERT_TRUE(eventually([&] { return loop.idle(); }));
  loop.stop();
  EXPECT_EQ(state.frames_integrated.load(), 0u);
  EXPECT_EQ(state.dropped.get(reason::kMapReplaced, "a"), 1u);
}

// Two cameras without poses start on an empty map at once: the first frame tracked defines the
// world, and the other camera is tracked against it once it is in the map, not given a second
// world of its own (it sees only a wall, which no keyframe can place: it stays lost).
TEST(FramePipeline, OnlyOneCameraDefinesTheWorldOfAnEmptyMap) {
  Mapper mapper(wallMapOptions());
  FrameQueue frames(16);
  ServerState state;
  PoseLog log;
  FusionLimits limits;
  limits.tracking_threads = 2;
  FusionLoop loop(mapper, frames, state, limits, log.callback());
  ASSERT_FALSE(frames.push(wallFrame("a", 1, false)));
  ASSERT_FALSE(frames.push(wallFrame("b", 1, false)));
  loop.start();
  ASSERT_TRUE(eventually([&] { return log.count.load() == 2 && loop.idle(); }));
  loop.stop();
  EXPECT_EQ(state.frames_integrated.load(), 1u);
  EXPECT_EQ(state.frames_lost.load(), 1u);
}
