// The live mesh end to end: a real semfuse-server fuses 300 frames of the synthetic room; a
// MapFollower that watched from the start and one that joined after the 300th frame end with the
// same blocks and the same vertex count in every block, which add up to the server's whole mesh;
// a reset empties them and the map that follows comes back.
#include <chrono>
#include <filesystem>
#include <map>
#include <thread>

#include <gtest/gtest.h>

#include "eventually.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/client/map_follower.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr int kFrames = 300;

synthetic::SequenceConfig sequenceConfig() {
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.25);  // 160x120 keeps 300 renderings quick
  config.trajectory.frame_count = kFrames;
  config.camera_id = "cam0";
  return config;
}

std::vector<std::string> serverArgs() {
  return {"--legend",           "synthetic", "--voxel-size",     "0.02", "--truncation",       "0.08",
          "--queue-per-camera", "400",       "--history-frames", "8",    "--map-updates.rate", "4",
          "--max-queue-wait",   "0"};
}

std::map<BlockOrigin, std::size_t> vertexCounts(const client::MapFollower& follower) {
  std::map<BlockOrigin, std::size_t> counts;
  follower.visit([&](const client::MapFollowerState& state) {
    for (const auto& [origin, block] : state.blocks) counts[origin] = block.vertexCount();
  });
  return counts;
}

// Up to date with `frames` integrated frames: an update or page of that map applied and every
// change up to it covered.
bool caughtUp(const client::MapFollower& follower, uint64_t frames, std::chrono::milliseconds timeout) {
  return follower.waitFor(
      [&](const client::MapFollowerState& s) {
        return s.header.frames_integrated >= frames && s.covered_revision >= s.header.revision;
      },
      timeout);
}

}  // namespace

TEST(MapUpdatesEndToEnd, AFollowerThatJoinsLateSeesTheMeshOfOneThatWatched) {
  ServerHarness h(serverTestDomain());
  h.startServer(serverArgs());
  client::MapFollower watcher(h.participant());
  watcher.start();

  synthetic::SyntheticSequence sequence(sequenceConfig());
  for (int i = 0; i < kFrames; ++i) {
    auto frame = sequence.frame(i);
    ASSERT_TRUE(frame.ok()) << frame.error();
    auto encoded = wire::encodeFrame(frame.value());
    ASSERT_TRUE(encoded.ok()) << encoded.error();
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    // One frame in flight: the frames writer keeps the last 2, so a loaded machine could
    // otherwise overwrite one the server has not read yet.
    ASSERT_TRUE(h.waitPose("cam0", static_cast<uint64_t>(i), 30s)) << "no pose for frame " << i;
    if (i == kFrames / 2) {
      // Mid-way the watcher already follows a growing mesh.
      EXPECT_TRUE(watcher.waitFor([](const client::MapFollowerState& s) { return !s.blocks.empty(); }, 20s));
    }
  }
  const auto status = h.waitStatus([](const auto& s) { return s.frames_integrated >= kFrames; }, 120s);
  ASSERT_EQ(status->frames_integrated, static_cast<uint64_t>(kFrames));

  client::MapFollower late(h.participant());
  late.start();
  ASSERT_TRUE(caughtUp(watcher, kFrames, 30s));
  ASSERT_TRUE(caughtUp(late, kFrames, 30s));
  // The mesher may still finish blocks of the last frames: both end with the same mesh.
  std::map<BlockOrigin, std::size_t> watched, joined;
  EXPECT_TRUE(eventually([&] {
    watched = vertexCounts(watcher);
    joined = vertexCounts(late);
    return watched == joined;
  }));
  EXPECT_GT(watched.size(), 300u);
  EXPECT_EQ(watched, joined);
  const client::MapFollowerStats late_stats = late.stats();
  EXPECT_GE(late_stats.catch_ups, 1u);
  EXPECT_GE(late_stats.pages, 1u);
  EXPECT_GT(watcher.stats().updates, 5u);

  // The blocks add up to the server's whole mesh: their own vertices are its vertices.
  std::size_t own = 0;
  watcher.visit([&](const client::MapFollowerState& s) { own = s.vertexCount(); });
  client::MapClient map(h.participant());
  auto mesh = map.mesh(std::nullopt, 30s);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  EXPECT_EQ(own, mesh.value().vertex_count);

  // A reset empties both; the frames that follow make a new mesh, which both follow.
  auto reset = map.reset(30s);
  ASSERT_TRUE(reset.ok()) << reset.error();
  for (auto* follower : {&watcher, &late})
    EXPECT_TRUE(follower->waitFor([](const client::MapFollowerState& s) { return s.blocks.empty(); }, 20s));
  for (int i = 0; i < 5; ++i) {
    auto encoded = wire::encodeFrame(sequence.frame(i).value());
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(h.waitPose("cam0", static_cast<uint64_t>(i), 30s)) << "no pose for frame " << i << " after the reset";
  }
  ASSERT_TRUE(caughtUp(watcher, 5, 30s));
  ASSERT_TRUE(caughtUp(late, 5, 30s));
  EXPECT_TRUE(eventually([&] {
    watched = vertexCounts(watcher);
    joined = vertexCounts(late);
    return watched == joined;
  }));
  EXPECT_FALSE(watched.empty());
  EXPECT_EQ(watched, joined);
  EXPECT_EQ(h.stopServer(), 0);
}
