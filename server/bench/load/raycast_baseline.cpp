#include "raycast_baseline.hpp"

#include <unistd.h>

#include <filesystem>

#include "semfuse/render/raycast.hpp"
#include "semfuse/volume/map_file.hpp"

namespace semfuse::bench::load {

RaycastBaseline measureIdleRaycasts(client::MapClient& map, const std::vector<Pose>& poses,
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
  if (!loaded) out.error = "load the saved map: " + loaded.error();
  render::RaycastOptions options;
  options.layers = kLayers;
  for (int r = 0; r < repeats; ++r)
    for (const Pose& pose : poses) {
      Stopwatch server_watch;
      auto reply = map.raycast(pose, intrinsics, kLayers, std::chrono::seconds(10));
      if (reply) out.server_ms.add(server_watch.elapsedMs());
      else out.error = "server raycast: " + reply.error();
      if (!loaded) continue;
      Stopwatch library_watch;
      auto images = render::raycast(loaded.value().volume, intrinsics, pose, options);
      if (images) out.library_ms.add(library_watch.elapsedMs());
      else out.error = "library raycast: " + images.error();
    }
  return out;
}

}  // namespace semfuse::bench::load
