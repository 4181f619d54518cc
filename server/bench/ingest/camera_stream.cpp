#include "camera_stream.hpp"

#include <thread>

#include "bench_support.hpp"
#include "interrupt.hpp"
#include "semfuse/wire/ros_codec.hpp"

namespace semfuse::bench::ingest {

std::size_t routeIndex(std::size_t step, std::size_t frames) {
  if (frames < 2) return 0;
  const std::size_t period = 2 * frames - 2;
  const std::size_t along = step % period;
  return along < frames ? along : period - along;
}

void runCamera(const Preloaded& data, const dds::Writer<FrameMsg>& writer, std::string camera_id,
               std::size_t first_index, std::chrono::steady_clock::time_point start,
               std::chrono::steady_clock::duration period, std::size_t slots, CameraResult& result,
               std::atomic<std::size_t>* current_index, bool with_poses) {
  using Clock = std::chrono::steady_clock;
  for (std::size_t slot = 0; slot < slots && !interrupted(); ++slot) {
    const auto due = start + period * static_cast<long>(slot);
    if (Clock::now() > due + period) {
      ++result.skipped_slots;
      continue;
    }
    std::this_thread::sleep_until(due);
    const std::size_t index = routeIndex(first_index + slot, data.frames.size());
    FrameMsg msg = data.frames[index].msg();
    msg.camera_id = camera_id.data();
    msg.seq = result.sent + result.write_failures;
    if (!with_poses) msg.has_pose = false;
    const Stamp now = wire::stampNow();
    msg.header.stamp.sec = now.sec;
    msg.header.stamp.nanosec = now.nanosec;
    Stopwatch write_watch;
    const Status written = writer.write(msg);
    result.write_ms.push_back(write_watch.elapsedMs());
    if (written) {
      ++result.sent;
      if (current_index) current_index->store(index);
    } else {
      ++result.write_failures;
    }
  }
}

}  // namespace semfuse::bench::ingest
