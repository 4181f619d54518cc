#pragma once
// OccupancyPublisher: the 2D occupancy grid on rt/semfuse/occupancy (nav_msgs/OccupancyGrid,
// reliable, transient-local, keep-last 1, as a ROS 2 map server's /map), for navigation stacks.
// Its thread (sf-occupancy) slices the distance field's band at most --occupancy.rate times a
// second, and only when the field changed since the last grid; a late joiner gets the last one.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include <nav_msgs.h>

#include "distance_field.hpp"
#include "esdf_config.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/writer.hpp"

namespace semfuse::server {

class OccupancyPublisher {
 public:
  OccupancyPublisher(const dds::Participant& participant, const DistanceField& field, const EsdfConfig& config);
  ~OccupancyPublisher();

  void start();  // nothing to do when the rate is 0
  void stop();

  uint64_t published() const { return published_.load(); }

 private:
  void run();

  const DistanceField& field_;
  EsdfConfig config_;
  dds::Topic<nav_msgs_msg_dds__OccupancyGrid_> topic_;
  dds::Writer<nav_msgs_msg_dds__OccupancyGrid_> writer_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool running_ = false;  // under mutex_
  std::thread thread_;
  std::atomic<uint64_t> published_{0};
};

}  // namespace semfuse::server
