// Segmenter: frames in, the user function's labels out on rt/semfuse/segmentations, and a slow
// function skips to the newest frame, or with a queue keeps every frame until it gets to them.
#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include SEMFUSE_DDS_TEST_ENV
#include "eventually.hpp"
#include "semfuse/client/camera_publisher.hpp"
#include "semfuse/client/segmenter.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/wire/message_codecs.hpp"

namespace semfuse::client {
namespace {

using SegmentationMsg = semfuse_msg_dds__Segmentation_;
using semfuse::testing::eventually;

Frame flatFrame(uint64_t seq, float depth_m) {
  Frame f;
  f.camera_id = "cam";
  f.seq = seq;
  f.intrinsics = {32, 24, 30.0, 30.0, 15.5, 11.5};
  f.depth = cv::Mat(24, 32, CV_32FC1, cv::Scalar(depth_m));
  return f;
}

class SegmenterTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dds::testing::useLoopbackConfig(); }
  dds::Participant participant_{dds::testing::testDomain()};
};

TEST_F(SegmenterTest, PublishesTheFunctionsLabelsForEachFrame) {
  dds::Topic<SegmentationMsg> topic(participant_, dds::topics::kSegmentations);
  dds::Reader<SegmentationMsg> results(topic, dds::qos::segmentations());
  // Label 2 for the far frame, 1 for the near one: the output must depend on the input.
  Segmenter segmenter(participant_,
                      [](const Frame& f) -> Result<Segmentation> {
                        Segmentation s;
                        s.labels =
                            cv::Mat(f.depth.size(), CV_16UC1, cv::Scalar(f.depth.at<float>(0, 0) > 1.0F ? 2 : 1));
                        s.confidence = cv::Mat(f.depth.size(), CV_32FC1, cv::Scalar(0.5F));
                        return s;
                      },
                      {"unit-test-segmenter", "", 1, std::chrono::milliseconds(0)});
  segmenter.start();
  CameraPublisher camera(participant_, {DepthEncoding::kRaw16, ColorEncoding::kNone, 90});
  ASSERT_TRUE(camera.waitForReader(std::chrono::seconds(15)));

  std::vector<Segmentation> received;
  ASSERT_TRUE(camera.publish(flatFrame(7, 2.0F)).ok());
  ASSERT_TRUE(eventually([&] {
    while (auto s = results.take()) received.push_back(wire::decodeSegmentation(**s).value());
    return !received.empty();
  }));
  ASSERT_TRUE(camera.publish(flatFrame(8, 0.5F)).ok());
  ASSERT_TRUE(eventually([&] {
    while (auto s = results.take()) received.push_back(wire::decodeSegmentation(**s).value());
    return received.size() >= 2;
  }));
  segmenter.stop();

  ASSERT_EQ(received.size(), 2u);
  EXPECT_EQ(received[0].frame_seq, 7u);
  EXPECT_EQ(received[0].camera_id, "cam");
  EXPECT_EQ(received[0].segmenter_id, "unit-test-segmenter");
  EXPECT_EQ(received[0].labels.size(), cv::Size(32, 24));
  EXPECT_EQ(cv::countNonZero(received[0].labels != 2), 0);
  EXPECT_EQ(received[1].frame_seq, 8u);
  EXPECT_EQ(cv::countNonZero(received[1].labels != 1), 0);
  EXPECT_NEAR(received[1].confidence.at<float>(3, 3), 0.5F, 1.0F / 255);
  const SegmenterStats stats = segmenter.stats();
  EXPECT_EQ(stats.received, 2u);
  EXPECT_EQ(stats.published, 2u);
  EXPECT_EQ(stats.skipped, 0u);
}

// A function that blocks on frame 0 while four more frames arrive one by one; returns the seqs it
// segmented, and the stats.
std::pair<std::vector<uint64_t>, SegmenterStats> segmentBehindASlowFirstFrame(const dds::Participant& participant,
                                                                              std::size_t queue) {
  std::mutex mutex;
  std::condition_variable changed;
  bool inside = false;
  bool release = false;
  std::vector<uint64_t> segmented;
  // The first call blocks until the test has delivered four more frames.
  Segmenter segmenter(participant,
                      [&](const Frame& f) -> Result<Segmentation> {
                        std::unique_lock lock(mutex);
                        segmented.push_back(f.seq);
                        inside = true;
                        changed.notify_all();
                        changed.wait(lock, [&] { return release; });
                        Segmentation s;
                        s.labels = cv::Mat(f.depth.size(), CV_16UC1, cv::Scalar(3));
                        return s;
                      },
                      {"slow", "", 1, std::chrono::milliseconds(0), queue});
  segmenter.start();
  CameraPublisher camera(participant, {DepthEncoding::kRaw16, ColorEncoding::kNone, 90});
  EXPECT_TRUE(camera.waitForReader(std::chrono::seconds(15)));

  EXPECT_TRUE(camera.publish(flatFrame(0, 1.0F)).ok());
  {
    std::unique_lock lock(mutex);
    EXPECT_TRUE(changed.wait_for(lock, std::chrono::seconds(20), [&] { return inside; }));
  }
  // One at a time: the reader keeps only the 2 newest frames (the frames QoS), so a burst could
  // lose frames before the receiving thread takes them, which is not what this test is about.
  for (uint64_t seq = 1; seq <= 4; ++seq) {
    EXPECT_TRUE(camera.publish(flatFrame(seq, 1.0F)).ok());
    EXPECT_TRUE(eventually([&] { return segmenter.stats().received == seq + 1; }));
  }
  {
    std::lock_guard lock(mutex);
    release = true;
  }
  changed.notify_all();
  EXPECT_TRUE(eventually([&] { return segmenter.stats().published == std::min<std::size_t>(queue, 4) + 1; }));
  segmenter.stop();

  return {segmented, segmenter.stats()};
}

TEST_F(SegmenterTest, ASlowFunctionSkipsToTheNewestFrame) {
  const auto [segmented, stats] = segmentBehindASlowFirstFrame(participant_, 1);
  EXPECT_EQ(segmented, (std::vector<uint64_t>{0, 4}));
  EXPECT_EQ(stats.skipped, 3u);
  EXPECT_EQ(stats.segmented, 2u);
}

TEST_F(SegmenterTest, AQueueKeepsEveryFrameForASlowFunction) {
  const auto [segmented, stats] = segmentBehindASlowFirstFrame(participant_, 4);
  EXPECT_EQ(segmented, (std::vector<uint64_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(stats.skipped, 0u);
  EXPECT_EQ(stats.segmented, 5u);
}

// A delay holds each result, not the worker: the next frame is segmented while the first result
// waits, results go out in order no earlier than the delay, and stop() publishes what is held.
TEST_F(SegmenterTest, ADelayedResultDoesNotHoldTheWorker) {
  constexpr auto kDelay = std::chrono::milliseconds(1500);
  dds::Topic<SegmentationMsg> topic(participant_, dds::topics::kSegmentations);
  dds::Reader<SegmentationMsg> results(topic, dds::qos::segmentations());
  Segmenter segmenter(participant_,
                      [](const Frame& f) -> Result<Segmentation> {
                        Segmentation s;
                        s.labels = cv::Mat(f.depth.size(), CV_16UC1, cv::Scalar(4));
                        return s;
                      },
                      {"late", "", 1, kDelay});
  segmenter.start();
  CameraPublisher camera(participant_, {DepthEncoding::kRaw16, ColorEncoding::kNone, 90});
  ASSERT_TRUE(camera.waitForReader(std::chrono::seconds(15)));

  const auto first_sent = std::chrono::steady_clock::now();
  ASSERT_TRUE(camera.publish(flatFrame(0, 1.0F)).ok());
  ASSERT_TRUE(eventually([&] { return segmenter.stats().segmented == 1; }));
  const auto first_segmented = std::chrono::steady_clock::now();
  ASSERT_TRUE(camera.publish(flatFrame(1, 1.0F)).ok());
  ASSERT_TRUE(eventually([&] { return segmenter.stats().segmented == 2; }));
  // A worker that slept through the delay would have published frame 0 before taking frame 1.
  // (Both frames were segmented within the delay unless the machine stalled for 1.5 s.)
  const bool within_delay = std::chrono::steady_clock::now() - first_segmented < kDelay;
  if (within_delay) {
    EXPECT_EQ(segmenter.stats().published, 0u);
  }

  std::vector<uint64_t> seqs;
  ASSERT_TRUE(eventually([&] {
    while (auto sample = results.take()) seqs.push_back((*sample)->frame_seq);
    return !seqs.empty();
  }));
  EXPECT_GE(std::chrono::steady_clock::now() - first_sent, kDelay);
  segmenter.stop();  // frame 1's result is still held, or just out: stop() publishes it
  ASSERT_TRUE(eventually([&] {
    while (auto sample = results.take()) seqs.push_back((*sample)->frame_seq);
    return seqs.size() >= 2;
  }));
  EXPECT_EQ(seqs, (std::vector<uint64_t>{0, 1}));
  EXPECT_EQ(segmenter.stats().published, 2u);
  EXPECT_EQ(segmenter.stats().skipped, 0u);
}

TEST_F(SegmenterTest, EveryNthFrameIsSelected) {
  std::mutex mutex;
  std::vector<uint64_t> segmented;
  Segmenter segmenter(participant_,
                      [&](const Frame& f) -> Result<Segmentation> {
                        std::lock_guard lock(mutex);
                        segmented.push_back(f.seq);
                        Segmentation s;
                        s.labels = cv::Mat(f.depth.size(), CV_16UC1, cv::Scalar(1));
                        return s;
                      },
                      {"every-third", "", 3, std::chrono::milliseconds(0)});
  segmenter.start();
  CameraPublisher camera(participant_, {DepthEncoding::kRaw16, ColorEncoding::kNone, 90});
  ASSERT_TRUE(camera.waitForReader(std::chrono::seconds(15)));
  // One at a time, so that the newest-frame rule never skips: only `every` selects.
  for (uint64_t seq = 10; seq < 17; ++seq) {
    ASSERT_TRUE(camera.publish(flatFrame(seq, 1.0F)).ok());
    ASSERT_TRUE(eventually([&] { return segmenter.stats().received == seq - 9; }));
    ASSERT_TRUE(eventually([&] {
      const auto s = segmenter.stats();
      return s.published + s.not_selected == s.received;
    }));
  }
  segmenter.stop();
  EXPECT_EQ(segmented, (std::vector<uint64_t>{10, 13, 16}));
  EXPECT_EQ(segmenter.stats().not_selected, 4u);
}

TEST_F(SegmenterTest, EveryCountsTheFollowedCamerasFramesOnly) {
  std::mutex mutex;
  std::vector<uint64_t> segmented;
  Segmenter segmenter(participant_,
                      [&](const Frame& f) -> Result<Segmentation> {
                        std::lock_guard lock(mutex);
                        segmented.push_back(f.seq);
                        Segmentation s;
                        s.labels = cv::Mat(f.depth.size(), CV_16UC1, cv::Scalar(1));
                        return s;
                      },
                      {"cam-every-second", "cam", 2, std::chrono::milliseconds(0)});
  segmenter.start();
  CameraPublisher camera(participant_, {DepthEncoding::kRaw16, ColorEncoding::kNone, 90});
  ASSERT_TRUE(camera.waitForReader(std::chrono::seconds(15)));
  // Another camera sends one frame, then two, between the followed camera's frames: which of
  // "cam"'s frames are segmented must not depend on it.
  uint64_t sent = 0;
  auto send = [&](const Frame& frame) {
    ASSERT_TRUE(camera.publish(frame).ok());
    ++sent;
    ASSERT_TRUE(eventually([&] {
      const auto s = segmenter.stats();
      return s.received == sent && s.published + s.not_selected == s.received;
    }));
  };
  for (uint64_t seq = 0; seq < 6; ++seq) {
    send(flatFrame(seq, 1.0F));
    for (uint64_t k = 0; k < 1 + seq % 2; ++k) {
      Frame other = flatFrame(100 + 2 * seq + k, 1.0F);
      other.camera_id = "other";
      send(other);
    }
  }
  segmenter.stop();
  EXPECT_EQ(segmented, (std::vector<uint64_t>{0, 2, 4}));
  // Nothing is dropped without a count: 3 of cam's frames by `every`, 9 of the other camera.
  EXPECT_EQ(segmenter.stats().not_selected, 12u);
}

}  // namespace
}  // namespace semfuse::client
