#pragma once
// The figures a load run is judged by, computed once from its result: per camera, how many of its
// frames got a pose and how soon, how many were integrated or skipped, its share of the
// integrations; and for the server, frames per second and per core.
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "load_result.hpp"

namespace semfuse::bench::load {

struct CameraFigures {
  std::string camera_id;
  bool posed_camera = true;  // sends its poses; else the server tracks it
  int64_t sent = 0, posed = 0, lost = 0, integrated = 0, skipped = 0;
  Timings pose_latency_ms;      // camera publish -> its TrackedPose received, posed frames
  double integrated_share = 0;  // integrated / the cameras' mean integrated (1 = fair)
};

struct LoadFigures {
  std::vector<CameraFigures> cameras;
  double duration_s = 0;
  int64_t sent = 0, posed = 0, lost = 0, integrated = 0, skipped = 0;
  int64_t tracked_sent = 0, tracked_posed = 0, tracked_lost = 0;  // cameras the server tracks
  Timings pose_latency_ms, tracked_pose_latency_ms;
  double posed_per_s = 0, integrated_per_s = 0;
  double server_cores = 0;           // server CPU over the run, in cores
  double integrated_per_core_s = 0;  // integrated frames per second of one core the server used
  double worst_share_deviation = 0;  // max |share - 1| over the cameras
  int64_t segmentations_sent = 0, segmentations_fused = 0;
};

LoadFigures loadFigures(const LoadResult& result);

}  // namespace semfuse::bench::load
