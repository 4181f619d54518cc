#pragma once
// One camera of the ingest and load benches: frames first_index, first_index+1, ... at slot times
// start + n * period, back along the sequence from its end and forth again from its start, as a
// robot that goes back along its route: a camera that jumped from the last frame to the first
// would be lost at every lap, which a moving robot never is. A slot that is already over when the previous write
// returns is skipped, not sent late in a burst: a real camera does not queue its frames either. Frames are numbered by
// write attempt, not by slot, so a skipped slot is no gap in the sequence the server sees (it would count one as a
// frame lost on the way). Without poses the camera sends none and the server tracks it.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include "msg.h"
#include "preloaded_frames.hpp"
#include "semfuse/dds/writer.hpp"

namespace semfuse::bench::ingest {

// The frame of a sequence of `frames` at `step` of the route 0, 1, ..., frames-1, frames-2, ..., 1, 0, 1, ...
std::size_t routeIndex(std::size_t step, std::size_t frames);

using FrameMsg = semfuse_msg_dds__Frame_;

struct CameraResult {
  std::size_t sent = 0, write_failures = 0, skipped_slots = 0;  // seqs 0 .. sent + write_failures - 1
  std::vector<double> write_ms;
};

// Publishes until the slots are done or the bench is interrupted; current_index (when given)
// follows the frame last sent, for the raycasts that look where the camera is.
void runCamera(const Preloaded& data, const dds::Writer<FrameMsg>& writer, std::string camera_id,
               std::size_t first_index, std::chrono::steady_clock::time_point start,
               std::chrono::steady_clock::duration period, std::size_t slots, CameraResult& result,
               std::atomic<std::size_t>* current_index, bool with_poses);

}  // namespace semfuse::bench::ingest
