// semfuse-server stopping while admin commands come in (a real process over loopback DDS): a load
// in progress when SIGTERM arrives finishes and is answered, a reset that comes in after the stop
// began is refused at once (UNAVAILABLE, "shutting down"), and the server exits within seconds
// instead of waiting out the admin service's 60 s wait for a fusion thread that has ended.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "semfuse/client/map_client.hpp"
#include "semfuse/volume/label_rules.hpp"
#include "semfuse/volume/labeled_volume.hpp"
#include "semfuse/volume/map_file.hpp"
#include "semfuse/volume/voxel.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr double kShutdownMapVoxel = 0.02;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A map that takes the server a while to load: a dense block of side^3 observed voxels, with the
// parameters the server below runs with.
void writeSlowMap(const std::filesystem::path& path, int side) {
  volume::VolumeParams params;
  params.voxel_size = kShutdownMapVoxel;
  params.truncation = 4 * kShutdownMapVoxel;
  params.label_rule = volume::LabelRule::kBayes;
  volume::LabeledVolume map(params);
  const openvdb::CoordBBox block(openvdb::Coord(0), openvdb::Coord(side - 1));
  map.mutableGeometryGrid().tree().denseFill(block, volume::packVoxel(0.01f, 1.0f, 1, 1.0f), true);
  if (auto* color = map.mutableColorGrid()) color->tree().denseFill(block, 0x808080, true);
  if (auto* sidecar = map.mutableLabelSidecarGrid()) sidecar->tree().denseFill(block, 0, true);
  map.setFramesIntegrated(1);
  Status saved = volume::saveMap(map, *builtinLegend("synthetic"), path);
  ASSERT_TRUE(saved.ok()) << saved.error();
}

// A folder of its own, removed however the test ends (the map in it is large).
struct TempFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("semfuse_shutdown_" + std::to_string(::getpid()));
  TempFolder() {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempFolder() { std::filesystem::remove_all(path); }
};

template <class T>
struct TimedCall {
  client::CallResult<T> result;
  double seconds;
};

}  // namespace

TEST(ServerShutdown, AnAdminCommandDuringTheStopIsAnsweredPromptlyAndTheServerExits) {
  TempFolder folder;
  const auto slow_map = folder.path / "slow.vdb";
  writeSlowMap(slow_map, 192);

  ServerHarness h(serverTestDomain());
  h.startServer({"--legend", "synthetic", "--voxel-size", std::to_string(kShutdownMapVoxel), "--truncation",
                 std::to_string(4 * kShutdownMapVoxel), "--label-rule", "bayes", "--autosave-period", "0"});
  client::MapClient loader(h.participant());
  client::MapClient resetter(h.participant());
  ASSERT_TRUE(loader.stats(30s).ok());
  ASSERT_TRUE(resetter.stats(30s).ok());

  // How long a load takes on this machine now: the stop must land in the middle of one.
  const auto first_start = std::chrono::steady_clock::now();
  auto first = loader.load(slow_map.string(), 60s);
  ASSERT_TRUE(first.ok()) << first.error();
  const double load_s = secondsSince(first_start);
  ASSERT_GT(load_s, 0.3) << "the map loads too fast for the stop to come during a load";

  // A load; a reset that waits behind it in the admin service; SIGTERM while the load runs.
  auto load = std::async(std::launch::async, [&] {
    const auto start = std::chrono::steady_clock::now();
    auto result = loader.load(slow_map.string(), 60s);
    return TimedCall<ServerStatus>{std::move(result), secondsSince(start)};
  });
  std::this_thread::sleep_for(std::chrono::duration<double>(0.2 * load_s));
  auto reset = std::async(std::launch::async, [&] {
    const auto start = std::chrono::steady_clock::now();
    auto result = resetter.reset(60s);
    return TimedCall<ServerStatus>{std::move(result), secondsSince(start)};
  });
  std::this_thread::sleep_for(std::chrono::duration<double>(0.1 * load_s));
  const auto stop_start = std::chrono::steady_clock::now();
  const int exit_code = h.stopServer();  // SIGTERM; SIGKILL after 20 s (exit code -1)
  const double stop_s = secondsSince(stop_start);

  EXPECT_EQ(exit_code, 0);
  EXPECT_LT(stop_s, load_s + 10.0) << "the server took " << stop_s << " s to stop";

  auto loaded = load.get();
  EXPECT_TRUE(loaded.result.ok()) << loaded.result.error();
  EXPECT_LT(loaded.seconds, 2 * load_s + 10.0) << "a load takes " << load_s << " s";

  auto refused = reset.get();
  ASSERT_FALSE(refused.result.ok()) << "the reset ran while the server stopped";
  EXPECT_EQ(refused.result.failure(), client::Failure::kServer) << refused.result.error();
  EXPECT_EQ(refused.result.errorCode(), ErrorCode::kUnavailable) << refused.result.error();
  EXPECT_NE(refused.result.error().find("shutting down"), std::string::npos) << refused.result.error();
  EXPECT_LT(refused.seconds, load_s + 10.0) << "a load takes " << load_s << " s";
}
