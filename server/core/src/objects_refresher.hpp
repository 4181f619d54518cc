#pragma once
// ObjectsRefresher: keeps the map's objects up to date while the map grows, on a thread of its own
// (sf-objects) at --objects-rate, at the queries' priority, so that an objects query that accepts
// a recent answer (ObjectsRequest::max_age_s) gets one at once and the object events flow without
// anyone polling. It regroups only while somebody wants objects: a reader of the object events,
// or an objects query in the last kIdleAfter; the same map again costs nothing.
#include <atomic>
#include <chrono>
#include <functional>

#include "map_access.hpp"
#include "periodic_thread.hpp"
#include "semfuse/objects/object_tracker.hpp"

namespace semfuse::server {

class ObjectsRefresher {
 public:
  static constexpr std::chrono::seconds kIdleAfter{30};

  // `listening`: whether the object events have a reader. No thread when rate_hz is 0.
  ObjectsRefresher(const MapAccess& map, objects::ObjectTracker& tracker, double rate_hz,
                   std::function<bool()> listening);
  ObjectsRefresher(const ObjectsRefresher&) = delete;
  ObjectsRefresher& operator=(const ObjectsRefresher&) = delete;

  // An objects query came: keep the objects up to date for kIdleAfter.
  void touch() { touched_at_ = std::chrono::steady_clock::now().time_since_epoch().count(); }

 private:
  bool wanted() const;

  const MapAccess& map_;
  objects::ObjectTracker& tracker_;
  std::function<bool()> listening_;
  std::atomic<std::chrono::steady_clock::rep> touched_at_{0};  // 0: never
  PeriodicThread rounds_;                                      // last: stops before what its rounds use goes
};

}  // namespace semfuse::server
