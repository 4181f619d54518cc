#include "load_figures.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "input_accounting.hpp"

namespace semfuse::bench::load {

LoadFigures loadFigures(const LoadResult& result) {
  LoadFigures out;
  out.duration_s = result.duration_s;
  std::map<std::string, CameraFigures*> by_id;
  const std::vector<InputAccount> accounts = accountInputs(result);
  for (std::size_t k = 0; k < result.cameras.size() && k < accounts.size(); ++k) {
    const InputAccount& account = accounts[k];
    CameraFigures camera;
    camera.camera_id = result.cameras[k].camera_id;
    camera.posed_camera = result.cameras[k].posed;
    camera.sent = account.sent;
    camera.posed = account.posed;
    camera.lost = account.dropped.count("tracking_lost") ? account.dropped.at("tracking_lost") : 0;
    camera.integrated = account.integrated;
    camera.skipped = account.skipped;
    out.cameras.push_back(std::move(camera));
  }
  for (auto& camera : out.cameras) by_id[camera.camera_id] = &camera;
  for (const auto& pose : result.poses) {
    const auto found = by_id.find(pose.camera_id);
    if (!pose.posed || found == by_id.end()) continue;
    found->second->pose_latency_ms.add(pose.latency_ms);
    out.pose_latency_ms.add(pose.latency_ms);
    if (!found->second->posed_camera) out.tracked_pose_latency_ms.add(pose.latency_ms);
  }
  for (const auto& camera : out.cameras) {
    out.sent += camera.sent;
    out.posed += camera.posed;
    out.lost += camera.lost;
    out.integrated += camera.integrated;
    out.skipped += camera.skipped;
    if (!camera.posed_camera) {
      out.tracked_sent += camera.sent;
      out.tracked_posed += camera.posed;
      out.tracked_lost += camera.lost;
    }
  }
  if (!out.cameras.empty() && out.integrated > 0) {
    const double mean = static_cast<double>(out.integrated) / static_cast<double>(out.cameras.size());
    for (auto& camera : out.cameras) {
      camera.integrated_share = static_cast<double>(camera.integrated) / mean;
      out.worst_share_deviation = std::max(out.worst_share_deviation, std::abs(camera.integrated_share - 1.0));
    }
  }
  if (out.duration_s > 0) {
    out.posed_per_s = static_cast<double>(out.posed) / out.duration_s;
    out.integrated_per_s = static_cast<double>(out.integrated) / out.duration_s;
  }
  out.server_cores = result.server_cpu_percent / 100.0;
  out.integrated_per_core_s = out.server_cores > 0 ? out.integrated_per_s / out.server_cores : 0;
  if (!accounts.empty()) {
    out.segmentations_sent = accounts.back().sent;
    out.segmentations_fused = accounts.back().integrated;
  }
  return out;
}

}  // namespace semfuse::bench::load
