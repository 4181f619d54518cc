#include "status_message.hpp"

#include <unistd.h>
#include <chrono>
#include <fstream>

#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/frame_codec.hpp"

namespace semfuse::server {
namespace {
void fillCounters(const std::vector<ReasonCount>& counters, dds_sequence_semfuse_msg_dds__Counter_& out) {
  dds::resizeSequence(out, counters.size());
  for (size_t i = 0; i < counters.size(); ++i) {
    dds::setString(out._buffer[i].reason, counters[i].reason);
    dds::setString(out._buffer[i].camera_id, counters[i].camera_id);
    out._buffer[i].count = counters[i].count;
  }
}
}  // namespace

void fillStatusMessage(const ServerStatus& s, semfuse_msg_dds__ServerStatus_& out) {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now).count();
  out.header.stamp.sec = static_cast<int32_t>(ns / 1000000000);
  out.header.stamp.nanosec = static_cast<uint32_t>(ns % 1000000000);
  dds::setString(out.header.frame_id, "world");
  dds::setString(out.server_id, s.server_id);
  dds::setString(out.version, s.version);
  out.uptime_s = s.uptime_s;
  out.frames_received = s.frames_received;
  out.frames_integrated = s.frames_integrated;
  out.frames_lost = s.frames_lost;
  out.segmentations_received = s.segmentations_received;
  out.segmentations_integrated = s.segmentations_integrated;
  fillCounters(s.dropped, out.dropped);
  fillCounters(s.rejected, out.rejected);
  out.queued_frames = s.queued_frames;
  out.pending_segmentations = s.pending_segmentations;
  out.history_frames = s.history_frames;
  out.voxel_size = s.voxel_size;
  out.truncation = s.truncation;
  out.allocated_voxels = s.allocated_voxels;
  out.allocated_blocks = s.allocated_blocks;
  out.map_bytes = s.map_bytes;
  out.rss_bytes = s.rss_bytes;

  dds::resizeSequence(out.cameras, s.cameras.size());
  for (size_t i = 0; i < s.cameras.size(); ++i) {
    auto& c = out.cameras._buffer[i];
    const CameraStatus& a = s.cameras[i];
    dds::setString(c.camera_id, a.camera_id);
    c.tracking_state = a.tracking_state;
    c.last_seq = a.last_seq;
    c.frames_received = a.frames_received;
    c.frames_integrated = a.frames_integrated;
    c.frames_lost = a.frames_lost;
    c.frame_rate_hz = a.frame_rate_hz;
    c.last_frame_age_s = a.last_frame_age_s;
    c.stale = a.stale;
  }
  dds::resizeSequence(out.last_errors, s.last_errors.size());
  for (size_t i = 0; i < s.last_errors.size(); ++i) {
    auto& e = out.last_errors._buffer[i];
    const double stamp = s.last_errors[i].stamp_s;
    e.stamp.sec = static_cast<int32_t>(stamp);
    e.stamp.nanosec = static_cast<uint32_t>((stamp - static_cast<double>(e.stamp.sec)) * 1e9);
    dds::setString(e.source, s.last_errors[i].source);
    dds::setString(e.message, s.last_errors[i].message);
  }
  dds::setString(out.map_file, s.map_file);
  out.last_save_ok = s.last_save_ok;
  out.last_save_age_s = s.last_save_age_s;
}

uint64_t currentRssBytes() {
  std::ifstream statm("/proc/self/statm");
  uint64_t pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0;
  return pages_resident * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

}  // namespace semfuse::server
