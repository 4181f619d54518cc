#include "objects_refresher.hpp"

#include <utility>

namespace semfuse::server {

using Clock = std::chrono::steady_clock;

ObjectsRefresher::ObjectsRefresher(const MapAccess& map, objects::ObjectTracker& tracker, double rate_hz,
                                   std::function<bool()> listening)
    : map_(map), tracker_(tracker), listening_(std::move(listening)) {
  if (!(rate_hz > 0.0)) return;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  // The same map again returns at once.
  rounds_.start("sf-objects", period, [this] {
    if (wanted()) tracker_.objectsOf(map_.snapshot());
  });
}

bool ObjectsRefresher::wanted() const {
  if (listening_ && listening_()) return true;
  const Clock::rep touched = touched_at_.load();
  return touched != 0 && Clock::now() - Clock::time_point(Clock::duration(touched)) < kIdleAfter;
}

}  // namespace semfuse::server
