#include "semfuse/wire/status_codec.hpp"

#include <string>
#include <vector>

#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::wire {
namespace {

void encodeCounters(const std::vector<ReasonCount>& counters, dds_sequence_semfuse_msg_dds__Counter_& out) {
  dds::resizeSequence(out, counters.size());
  for (size_t i = 0; i < counters.size(); ++i) {
    dds::setString(out._buffer[i].reason, counters[i].reason);
    dds::setString(out._buffer[i].camera_id, counters[i].camera_id);
    out._buffer[i].count = counters[i].count;
  }
}

Result<std::vector<ReasonCount>> decodeCounters(const std::string& what,
                                                const dds_sequence_semfuse_msg_dds__Counter_& seq) {
  if (Status s = validateSequence(what, seq._length, seq._maximum, seq._buffer); !s) return makeError(s.error());
  std::vector<ReasonCount> out;
  out.reserve(seq._length);
  for (uint32_t i = 0; i < seq._length; ++i) {
    out.push_back({stringOf(seq._buffer[i].reason), stringOf(seq._buffer[i].camera_id), seq._buffer[i].count});
  }
  return out;
}

}  // namespace

void encodeServerStatus(const ServerStatus& s, Stamp stamp, semfuse_msg_dds__ServerStatus_& out) {
  out.header.stamp.sec = stamp.sec;
  out.header.stamp.nanosec = stamp.nanosec;
  dds::setString(out.header.frame_id, "world");
  dds::setString(out.server_id, s.server_id);
  dds::setString(out.version, s.version);
  out.uptime_s = s.uptime_s;
  out.frames_received = s.frames_received;
  out.frames_posed = s.frames_posed;
  out.frames_integrated = s.frames_integrated;
  out.frames_skipped = s.frames_skipped;
  out.frames_lost = s.frames_lost;
  out.segmentations_received = s.segmentations_received;
  out.segmentations_integrated = s.segmentations_integrated;
  encodeCounters(s.dropped, out.dropped);
  encodeCounters(s.rejected, out.rejected);
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
    c.frames_posed = a.frames_posed;
    c.frames_integrated = a.frames_integrated;
    c.frames_skipped = a.frames_skipped;
    c.frames_lost = a.frames_lost;
    c.frame_rate_hz = a.frame_rate_hz;
    c.last_frame_age_s = a.last_frame_age_s;
    c.stale = a.stale;
    dds::setString(c.lost_reason, a.lost_reason);
    c.frames_since_lost = a.frames_since_lost;
    c.relocalisations = a.relocalisations;
  }
  dds::resizeSequence(out.last_errors, s.last_errors.size());
  for (size_t i = 0; i < s.last_errors.size(); ++i) {
    auto& e = out.last_errors._buffer[i];
    const double error_stamp = s.last_errors[i].stamp_s;
    e.stamp.sec = static_cast<int32_t>(error_stamp);
    e.stamp.nanosec = static_cast<uint32_t>((error_stamp - static_cast<double>(e.stamp.sec)) * 1e9);
    dds::setString(e.source, s.last_errors[i].source);
    dds::setString(e.message, s.last_errors[i].message);
  }
  dds::setString(out.map_file, s.map_file);
  out.last_save_ok = s.last_save_ok;
  out.last_save_age_s = s.last_save_age_s;
  dds::resizeSequence(out.stages, s.stages.size());
  for (size_t i = 0; i < s.stages.size(); ++i) {
    auto& t = out.stages._buffer[i];
    const StageTiming& a = s.stages[i];
    dds::setString(t.stage, a.stage);
    t.count = a.count;
    t.p50_ms = a.p50_ms;
    t.p95_ms = a.p95_ms;
    t.max_ms = a.max_ms;
  }
  out.map_revision = s.map_revision;
  out.distance_field_revision = s.distance_field_revision;
  out.snapshot_bytes = s.snapshot_bytes;
}

Result<ServerStatus> decodeServerStatus(const semfuse_msg_dds__ServerStatus_& msg) {
  ServerStatus s;
  s.server_id = stringOf(msg.server_id);
  s.version = stringOf(msg.version);
  s.uptime_s = msg.uptime_s;
  s.frames_received = msg.frames_received;
  s.frames_posed = msg.frames_posed;
  s.frames_integrated = msg.frames_integrated;
  s.frames_skipped = msg.frames_skipped;
  s.frames_lost = msg.frames_lost;
  s.segmentations_received = msg.segmentations_received;
  s.segmentations_integrated = msg.segmentations_integrated;
  auto dropped = decodeCounters("status dropped", msg.dropped);
  if (!dropped) return makeError(dropped.error());
  s.dropped = std::move(dropped).value();
  auto rejected = decodeCounters("status rejected", msg.rejected);
  if (!rejected) return makeError(rejected.error());
  s.rejected = std::move(rejected).value();
  s.queued_frames = msg.queued_frames;
  s.pending_segmentations = msg.pending_segmentations;
  s.history_frames = msg.history_frames;
  s.voxel_size = msg.voxel_size;
  s.truncation = msg.truncation;
  s.allocated_voxels = msg.allocated_voxels;
  s.allocated_blocks = msg.allocated_blocks;
  s.map_bytes = msg.map_bytes;
  s.rss_bytes = msg.rss_bytes;
  if (Status ok = validateSequence("status cameras", msg.cameras._length, msg.cameras._maximum, msg.cameras._buffer);
      !ok)
    return makeError(ok.error());
  for (uint32_t i = 0; i < msg.cameras._length; ++i) {
    const auto& c = msg.cameras._buffer[i];
    CameraStatus camera;
    camera.camera_id = stringOf(c.camera_id);
    camera.tracking_state = c.tracking_state;
    camera.last_seq = c.last_seq;
    camera.frames_received = c.frames_received;
    camera.frames_posed = c.frames_posed;
    camera.frames_integrated = c.frames_integrated;
    camera.frames_skipped = c.frames_skipped;
    camera.frames_lost = c.frames_lost;
    camera.frame_rate_hz = c.frame_rate_hz;
    camera.last_frame_age_s = c.last_frame_age_s;
    camera.stale = c.stale;
    camera.lost_reason = stringOf(c.lost_reason);
    camera.frames_since_lost = c.frames_since_lost;
    camera.relocalisations = c.relocalisations;
    s.cameras.push_back(std::move(camera));
  }
  if (Status ok = validateSequence("status last_errors", msg.last_errors._length, msg.last_errors._maximum,
                                   msg.last_errors._buffer);
      !ok)
    return makeError(ok.error());
  for (uint32_t i = 0; i < msg.last_errors._length; ++i) {
    const auto& e = msg.last_errors._buffer[i];
    s.last_errors.push_back({e.stamp.sec + e.stamp.nanosec * 1e-9, stringOf(e.source), stringOf(e.message)});
  }
  s.map_file = stringOf(msg.map_file);
  s.last_save_ok = msg.last_save_ok;
  s.last_save_age_s = msg.last_save_age_s;
  if (Status ok = validateSequence("status stages", msg.stages._length, msg.stages._maximum, msg.stages._buffer); !ok)
    return makeError(ok.error());
  for (uint32_t i = 0; i < msg.stages._length; ++i) {
    const auto& t = msg.stages._buffer[i];
    s.stages.push_back({stringOf(t.stage), t.count, t.p50_ms, t.p95_ms, t.max_ms});
  }
  s.map_revision = msg.map_revision;
  s.distance_field_revision = msg.distance_field_revision;
  s.snapshot_bytes = msg.snapshot_bytes;
  return s;
}

}  // namespace semfuse::wire
