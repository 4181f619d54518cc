#include "server_state.hpp"

#include <spdlog/spdlog.h>

namespace semfuse::server {

void ServerState::reject(const char* why, const std::string& camera_id, const std::string& source,
                         const std::string& message) {
  rejected.add(why, camera_id);
  errors.record(source, message);
  spdlog::warn("{}: rejected ({}): {}", source, why, message);
  touch();
}

void ServerState::frameArrived(const std::string& camera_id, uint64_t seq, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  CameraActivity& camera = cameras_[camera_id];
  // Frames that DDS delivered to nobody (the reader's keep-last history overwrote them before the
  // ingest thread took them, or the network lost them) show up as gaps in the camera's sequence.
  // A sequence that goes backwards is a restarted camera, not a loss.
  if (camera.frames_received > 0 && seq > camera.last_seq + 1)
    dropped.add(reason::kSequenceGap, camera_id, seq - camera.last_seq - 1);
  if (camera.frames_received > 0) {
    const double dt = std::chrono::duration<double>(now - camera.last_frame_time).count();
    if (dt > 0.0) {
      const double instant = 1.0 / dt;
      camera.rate_hz = camera.rate_hz == 0.0 ? instant : 0.9 * camera.rate_hz + 0.1 * instant;
    }
  }
  camera.last_frame_time = now;
  camera.last_seq = seq;
  ++camera.frames_received;
  touch();
}

void ServerState::frameTracked(const std::string& camera_id, const TrackResult& result) {
  (result.posed ? frames_posed : frames_lost)++;
  std::lock_guard lock(mutex_);
  CameraActivity& camera = cameras_[camera_id];
  camera.tracking_state = result.tracking_state;
  camera.lost_reason = result.lost_reason;
  camera.frames_since_lost = result.frames_since_lost;
  camera.relocalisations = result.relocalisations;
  ++(result.posed ? camera.frames_posed : camera.frames_lost);
  touch();
}

void ServerState::frameIntegrated(const std::string& camera_id) {
  ++frames_integrated;
  std::lock_guard lock(mutex_);
  ++cameras_[camera_id].frames_integrated;
  touch();
}

void ServerState::frameSkipped(const std::string& camera_id) {
  ++frames_skipped;
  std::lock_guard lock(mutex_);
  ++cameras_[camera_id].frames_skipped;
  touch();
}

std::map<std::string, CameraActivity> ServerState::cameras() const {
  std::lock_guard lock(mutex_);
  return cameras_;
}

bool ServerState::knowsCamera(const std::string& camera_id) const {
  std::lock_guard lock(mutex_);
  return cameras_.count(camera_id) > 0;
}

}  // namespace semfuse::server
