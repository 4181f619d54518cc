// The server's bookkeeping: bounded queues keep the newest frames, the history finds frames for
// late segmentations and forgets the oldest, waiting segmentations time out, counters add up.
#include <thread>

#include <gtest/gtest.h>

#include "event_counters.hpp"
#include "frame_history.hpp"
#include "frame_queue.hpp"
#include "pending_segmentations.hpp"

using namespace semfuse;
using namespace semfuse::server;
using namespace std::chrono_literals;

namespace {
Frame makeFrame(const std::string& camera, uint64_t seq) {
  Frame f;
  f.camera_id = camera;
  f.seq = seq;
  return f;
}
Segmentation makeSegmentation(const std::string& camera, uint64_t seq) {
  Segmentation s;
  s.camera_id = camera;
  s.frame_seq = seq;
  return s;
}
HistoryEntry makeEntry(const std::string& camera, uint64_t seq, int depth_pixels) {
  HistoryEntry e;
  e.camera_id = camera;
  e.seq = seq;
  e.posed = depth_pixels > 0;
  if (depth_pixels > 0) e.depth = cv::Mat(1, depth_pixels, CV_32FC1, cv::Scalar(1.0f));
  return e;
}
}  // namespace

TEST(FrameQueue, FullQueueDropsOldestAndKeepsNewest) {
  FrameQueue queue(2);
  EXPECT_FALSE(queue.push(makeFrame("cam", 1)));
  EXPECT_FALSE(queue.push(makeFrame("cam", 2)));
  auto evicted = queue.push(makeFrame("cam", 3));
  ASSERT_TRUE(evicted);
  EXPECT_EQ(evicted->seq, 1u);
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_EQ(queue.pop(10ms)->seq, 2u);
  EXPECT_EQ(queue.pop(10ms)->seq, 3u);
  EXPECT_FALSE(queue.pop(1ms));
}

TEST(FrameQueue, CamerasAreServedRoundRobinAndBoundedSeparately) {
  FrameQueue queue(3);
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_FALSE(queue.push(makeFrame("a", s)));
  EXPECT_FALSE(queue.push(makeFrame("b", 10)));  // b has its own bound
  EXPECT_FALSE(queue.push(makeFrame("b", 11)));
  std::vector<std::string> order;
  while (auto f = queue.pop(1ms)) order.push_back(f->camera_id + std::to_string(f->seq));
  EXPECT_EQ(order, (std::vector<std::string>{"a1", "b10", "a2", "b11", "a3"}));
}

TEST(FrameQueue, ACameraBehindForGoodHasItsNewestTakenAndTheOthersPassedOver) {
  FrameQueue queue(4, 20ms, 100ms);
  for (uint64_t s = 1; s <= 4; ++s) EXPECT_FALSE(queue.push(makeFrame("a", s)));
  std::this_thread::sleep_for(40ms);  // a hiccup: every frame queued so far waited too long
  std::vector<Frame> stale;
  EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, 1u);  // behind, but not for long: in order
  EXPECT_TRUE(stale.empty());

  // Still behind at each turn for longer than the backlog time: the newest is taken, the frames
  // before it are handed back.
  std::this_thread::sleep_for(120ms);
  EXPECT_FALSE(queue.push(makeFrame("a", 5)));
  std::chrono::steady_clock::duration waited{};
  auto frame = queue.pop(10ms, &waited, &stale);
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->seq, 5u);
  ASSERT_EQ(stale.size(), 3u);
  EXPECT_EQ(stale[0].seq, 2u);
  EXPECT_EQ(stale[2].seq, 4u);
  EXPECT_EQ(queue.size(), 0u);

  // A lone frame that waited too long is taken: there is nothing newer to take instead.
  stale.clear();
  EXPECT_FALSE(queue.push(makeFrame("a", 6)));
  std::this_thread::sleep_for(40ms);
  frame = queue.pop(10ms, &waited, &stale);
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->seq, 6u);
  EXPECT_GE(waited, 40ms);
  EXPECT_TRUE(stale.empty());
}

TEST(FrameQueue, ACameraThatCatchesUpStartsItsBacklogTimeAgain) {
  // Waits of 100 ms and more, so that a busy machine's scheduling delays between a push and the
  // next pop do not make a caught-up turn late.
  FrameQueue queue(4, 100ms, 500ms);
  std::vector<Frame> stale;
  EXPECT_FALSE(queue.push(makeFrame("a", 1)));
  EXPECT_FALSE(queue.push(makeFrame("a", 2)));
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, 1u);  // behind from here
  EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, 2u);
  // Caught up: a fresh frame at its turn ends the backlog, so a later hiccup starts afresh.
  EXPECT_FALSE(queue.push(makeFrame("a", 3)));
  EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, 3u);
  std::this_thread::sleep_for(400ms);
  EXPECT_FALSE(queue.push(makeFrame("a", 4)));
  EXPECT_FALSE(queue.push(makeFrame("a", 5)));
  std::this_thread::sleep_for(200ms);  // 600 ms after the first hiccup began, 200 ms into this one
  EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, 4u);
  EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, 5u);
  EXPECT_TRUE(stale.empty());
}

TEST(FrameQueue, FramesThatDidNotWaitTooLongAreTakenInOrder) {
  FrameQueue patient(4, 10s, 10s);
  std::vector<Frame> stale;
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_FALSE(patient.push(makeFrame("a", s)));
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_EQ(patient.pop(10ms, nullptr, &stale)->seq, s);
  EXPECT_TRUE(stale.empty());
}

TEST(FrameQueue, WithoutAMaximumWaitEveryFrameIsTakenInOrder) {
  FrameQueue queue(4);
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_FALSE(queue.push(makeFrame("a", s)));
  std::this_thread::sleep_for(20ms);
  std::vector<Frame> stale;
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_EQ(queue.pop(10ms, nullptr, &stale)->seq, s);
  EXPECT_TRUE(stale.empty());
}
TEST(FrameQueue, WakeReleasesAWaitingPop) {
  FrameQueue queue(2);
  std::thread waker([&] {
    std::this_thread::sleep_for(20ms);
    queue.wake();
  });
  auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(queue.pop(5s));
  EXPECT_LT(std::chrono::steady_clock::now() - start, 4s);
  waker.join();
}

TEST(FrameHistory, FindsFramesAndEvictsOldestByCount) {
  FrameHistory history(3, 1u << 30);
  for (uint64_t s = 1; s <= 5; ++s) history.add(makeEntry("cam", s, 100));
  EXPECT_EQ(history.size(), 3u);
  EXPECT_EQ(history.evicted(), 2u);
  EXPECT_EQ(history.find("cam", 1), nullptr);
  EXPECT_EQ(history.find("cam", 2), nullptr);
  ASSERT_NE(history.find("cam", 3), nullptr);
  EXPECT_EQ(history.find("cam", 5)->seq, 5u);
  EXPECT_EQ(history.find("other", 5), nullptr);
  EXPECT_EQ(history.lastSeq("cam"), 5u);
  EXPECT_FALSE(history.lastSeq("other"));
}

TEST(FrameHistory, EvictsByMemory) {
  const int pixels = 1000;  // 4000 bytes of depth each
  FrameHistory history(100, 3 * (pixels * 4 + sizeof(HistoryEntry)));
  for (uint64_t s = 1; s <= 4; ++s) history.add(makeEntry("cam", s, pixels));
  EXPECT_EQ(history.size(), 3u);
  EXPECT_EQ(history.find("cam", 1), nullptr);
  EXPECT_LE(history.bytes(), 3 * (pixels * 4 + sizeof(HistoryEntry)));
}

TEST(FrameHistory, RestartedSequenceReplacesEntry) {
  FrameHistory history(10, 1u << 30);
  history.add(makeEntry("cam", 7, 10));
  history.add(makeEntry("cam", 7, 20));
  EXPECT_EQ(history.size(), 1u);
  EXPECT_EQ(history.find("cam", 7)->depth.total(), 20u);
}

TEST(PendingSegmentations, MatchesByCameraAndSeqAndExpires) {
  PendingSegmentations pending(8, 100ms);
  auto t0 = PendingSegmentations::Clock::now();
  EXPECT_TRUE(pending.add(makeSegmentation("a", 5), t0).empty());
  EXPECT_TRUE(pending.add(makeSegmentation("b", 5), t0).empty());
  EXPECT_TRUE(pending.add(makeSegmentation("a", 5), t0 + 50ms).empty());  // a second segmenter
  EXPECT_TRUE(pending.add(makeSegmentation("a", 6), t0 + 80ms).empty());

  auto matched = pending.takeFor("a", 5);
  EXPECT_EQ(matched.size(), 2u);
  EXPECT_EQ(pending.size(), 2u);

  auto expired = pending.expire(t0 + 150ms);  // only b/5 waited more than 100 ms
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired[0].camera_id, "b");
  EXPECT_EQ(pending.size(), 1u);
}

TEST(PendingSegmentations, ReleasesOnlyThoseOfTheCameraBeforeTheFusedFrame) {
  PendingSegmentations pending(8, 10s);
  for (uint64_t seq : {3u, 5u, 7u}) EXPECT_TRUE(pending.add(makeSegmentation("a", seq)).empty());
  EXPECT_TRUE(pending.add(makeSegmentation("b", 2)).empty());
  auto orphaned = pending.takeBefore("a", 6);  // frames a/3 and a/5 will not come once a/6 is fused
  ASSERT_EQ(orphaned.size(), 2u);
  EXPECT_EQ(orphaned[0].frame_seq, 3u);
  EXPECT_EQ(orphaned[1].frame_seq, 5u);
  EXPECT_TRUE(pending.takeBefore("a", 6).empty());
  EXPECT_EQ(pending.size(), 2u);  // a/7 and the other camera's b/2 still wait
  EXPECT_EQ(pending.takeFor("a", 7).size(), 1u);
  EXPECT_EQ(pending.takeFor("b", 2).size(), 1u);
}

TEST(PendingSegmentations, FullSetEvictsOldest) {
  PendingSegmentations pending(2, 10s);
  EXPECT_TRUE(pending.add(makeSegmentation("a", 1)).empty());
  EXPECT_TRUE(pending.add(makeSegmentation("a", 2)).empty());
  auto evicted = pending.add(makeSegmentation("a", 3));
  ASSERT_EQ(evicted.size(), 1u);
  EXPECT_EQ(evicted[0].frame_seq, 1u);
}

TEST(EventCounters, CountsByReasonAndCamera) {
  EventCounters counters;
  counters.add("queue_full", "cam0");
  counters.add("queue_full", "cam0", 2);
  counters.add("bad_pose", "cam1");
  EXPECT_EQ(counters.get("queue_full", "cam0"), 3u);
  EXPECT_EQ(counters.get("queue_full", "cam1"), 0u);
  const auto snap = counters.snapshot();  // one entry per (reason, camera) that occurred
  ASSERT_EQ(snap.size(), 2u);
  EXPECT_EQ(snap[0].reason, "bad_pose");
  EXPECT_EQ(snap[0].camera_id, "cam1");
  EXPECT_EQ(snap[0].count, 1u);
  EXPECT_EQ(snap[1].reason, "queue_full");
  EXPECT_EQ(snap[1].camera_id, "cam0");
  EXPECT_EQ(snap[1].count, 3u);
}

TEST(ErrorLog, KeepsTheNewestErrors) {
  ErrorLog log(2);
  log.record("ingest", "first");
  log.record("ingest", "second");
  log.record("query", "third");
  auto snap = log.snapshot();
  ASSERT_EQ(snap.size(), 2u);
  EXPECT_EQ(snap[0].message, "second");
  EXPECT_EQ(snap[1].source, "query");
}
