#include "raycast_baseline.hpp"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "ingest/process_stats.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/volume/map_file.hpp"

namespace semfuse::bench::load {
namespace {

constexpr double kQuietPercent = 5.0;  // of one core
constexpr auto kQuietWindow = std::chrono::milliseconds(500);
constexpr auto kQuietBound = std::chrono::seconds(30);

// Waits until the process used less than kQuietPercent over a whole window; false when it was
// still busy at the bound.
bool waitUntilQuiet(pid_t pid, double& waited_s) {
  const auto start = std::chrono::steady_clock::now();
  ingest::CpuSample before = ingest::sampleCpu(pid);
  for (;;) {
    std::this_thread::sleep_for(kQuietWindow);
    const ingest::CpuSample after = ingest::sampleCpu(pid);
    waited_s = std::chrono::duration<double>(after.when - start).count();
    if (after.when > before.when && ingest::processPercent(before, after) < kQuietPercent) return true;
    if (after.when - start > kQuietBound) return false;
    before = after;
  }
}

}  // namespace

RaycastBaseline measureIdleRaycasts(client::MapClient& map, pid_t server, const std::vector<Pose>& poses,
                                    const PinholeIntrinsics& intrinsics, int repeats) {
  constexpr uint32_t kLayers = client::kDepthLayer | client::kNormalsLayer | client::kLabelsLayer;
  RaycastBaseline out;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("semfuse-bench-load-" + std::to_string(::getpid()) + ".vdb");
  if (auto saved = map.save(path.string(), std::chrono::seconds(120)); !saved) {
    out.error = "admin save: " + saved.error();
    return out;
  }
  auto loaded = volume::loadMap(path);
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  if (!loaded) {
    out.error = "load the saved map: " + loaded.error();
    return out;
  }
  out.quiet = waitUntilQuiet(server, out.quiet_wait_s);
  render::RaycastOptions options;
  options.layers = kLayers;
  // Round 0 warms both up and is not counted.
  for (int r = 0; r <= repeats; ++r)
    for (const Pose& pose : poses) {
      Stopwatch server_watch;
      auto reply = map.raycast(pose, intrinsics, kLayers, std::chrono::seconds(10));
      const double server_ms = server_watch.elapsedMs();
      Stopwatch library_watch;
      auto images = render::raycast(loaded.value().volume, intrinsics, pose, options);
      const double library_ms = library_watch.elapsedMs();
      if (!reply) out.error = "server raycast: " + reply.error();
      if (!images) out.error = "library raycast: " + images.error();
      if (r == 0 || !reply || !images) continue;
      out.server_ms.add(server_ms);
      out.library_ms.add(library_ms);
      out.ratio.add(server_ms / library_ms);
    }
  return out;
}

}  // namespace semfuse::bench::load
