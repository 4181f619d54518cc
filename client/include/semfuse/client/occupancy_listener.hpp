#pragma once
// OccupancyListener: follows the server's 2D occupancy grid on rt/semfuse/occupancy
// (nav_msgs/OccupancyGrid, transient-local: a new listener gets the latest grid at once),
// published with --esdf at --occupancy.rate when the map changed. A grid that does not decode is
// left out and counted.
//
//   semfuse::client::OccupancyListener occupancy(participant);
//   if (auto grid = occupancy.waitForGrid(std::chrono::seconds(5)))
//     plan(grid->cells, grid->width, grid->height, grid->resolution, grid->origin);
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

#include "semfuse/core/distance_service_types.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::client {

class OccupancyListener {
 public:
  explicit OccupancyListener(const dds::Participant& participant);
  ~OccupancyListener();
  OccupancyListener(const OccupancyListener&) = delete;
  OccupancyListener& operator=(const OccupancyListener&) = delete;

  // The newest grid received so far (nullopt before the first).
  std::optional<OccupancyGrid> latest();
  // A grid newer than the last one returned, waiting up to `timeout` for it.
  std::optional<OccupancyGrid> waitForGrid(std::chrono::milliseconds timeout);
  uint64_t received() const;
  uint64_t rejected() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semfuse::client
