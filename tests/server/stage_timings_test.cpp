// The server's stage timings: nearest-rank percentiles over each stage's last 1,000 runs, counts
// since the start, stages that never ran left out, bad samples ignored.
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "stage_timings.hpp"

namespace semfuse::server {
namespace {

TEST(StageTimings, PercentilesOfKnownSamplesInPipelineOrder) {
  StageTimings timings;
  for (int ms = 200; ms >= 1; --ms) timings.record(Stage::kIntegrate, ms);
  timings.record(Stage::kFrameDecode, 2.5);
  const std::vector<StageTiming> summary = timings.summary();
  ASSERT_EQ(summary.size(), 2u);  // the stages that never ran are left out
  EXPECT_EQ(summary[0].stage, "frame_decode");
  EXPECT_EQ(summary[0].count, 1u);
  EXPECT_FLOAT_EQ(summary[0].p50_ms, 2.5F);
  EXPECT_FLOAT_EQ(summary[0].max_ms, 2.5F);
  EXPECT_EQ(summary[1].stage, "integrate");
  EXPECT_EQ(summary[1].count, 200u);
  EXPECT_FLOAT_EQ(summary[1].p50_ms, 100.0F);
  EXPECT_FLOAT_EQ(summary[1].p95_ms, 190.0F);
  EXPECT_FLOAT_EQ(summary[1].max_ms, 200.0F);
}

TEST(StageTimings, PercentilesCoverTheLastThousandRunsAndCountAll) {
  StageTimings timings;
  for (int ms = 1; ms <= 2500; ++ms) timings.record(Stage::kFrameQueue, ms);
  const StageTiming t = timings.summary().at(0);
  EXPECT_EQ(t.count, 2500u);
  EXPECT_FLOAT_EQ(t.p50_ms, 2000.0F);  // of 1501..2500
  EXPECT_FLOAT_EQ(t.p95_ms, 2450.0F);
  EXPECT_FLOAT_EQ(t.max_ms, 2500.0F);
}

TEST(StageTimings, IgnoresNonFiniteSamplesAndClampsNegativeOnes) {
  StageTimings timings;
  timings.record(Stage::kTrack, std::nan(""));
  timings.record(Stage::kTrack, INFINITY);
  EXPECT_TRUE(timings.summary().empty());
  timings.record(Stage::kTrack, -3.0);  // a clock that stepped back
  ASSERT_EQ(timings.summary().size(), 1u);
  EXPECT_FLOAT_EQ(timings.summary()[0].max_ms, 0.0F);
}

TEST(StageTimings, ARunSinceAStartIsTheTimeElapsedInMilliseconds) {
  StageTimings timings;
  const auto start = std::chrono::steady_clock::now() - std::chrono::milliseconds(250);
  timings.recordSince(Stage::kFrameDecode, start);
  const auto summary = timings.summary();
  ASSERT_EQ(summary.size(), 1u);
  EXPECT_EQ(summary[0].stage, "frame_decode");
  EXPECT_GE(summary[0].max_ms, 250.0F);
  EXPECT_LT(summary[0].max_ms, 10'000.0F);  // milliseconds, not seconds or nanoseconds
}

TEST(StageTimings, ThreadsRecordingAtOnceLoseNothing) {
  StageTimings timings;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 5000; ++i) timings.record(Stage::kMapUpdate, 1.0);
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(timings.summary().at(0).count, 20000u);
}

}  // namespace
}  // namespace semfuse::server
