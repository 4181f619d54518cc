#pragma once
// FusionServer: semfuse-server assembled. Owns the DDS participant, the map (Mapper), the
// ingest, tracking and fusion threads, the query services, the status/pose/legend publishers and
// persistence (resume at start, autosave, save at shutdown).
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>

#include "distance_field.hpp"
#include "frame_queue.hpp"
#include "fusion_loop.hpp"
#include "ingest.hpp"
#include "map_update_publisher.hpp"
#include "mapper.hpp"
#include "mapper_access.hpp"
#include "occupancy_publisher.hpp"
#include "process_memory.hpp"
#include "ros_ingest.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/writer.hpp"
#include "server_config.hpp"
#include "server_state.hpp"
#include "services.hpp"

namespace semfuse::server {

class FusionServer {
 public:
  // Throws std::runtime_error with a clear message when it cannot start (bad config, DDS).
  explicit FusionServer(ServerConfig config);
  ~FusionServer();

  // Serves until requestStop() (e.g. from a signal handler thread), then runs the stop sequence
  // (stop()), saves the map and publishes a last status. Returns 1 when that save fails.
  int run();
  void requestStop() { stop_requested_ = true; }

  ServerStatus snapshot() const;

 private:
  // The stop sequence, for run() and the destructor alike; the second call does nothing.
  void stop();
  void publishStatus();
  void frameTracked(const PosedFrame& frame);  // the tracking threads' callback
  void publishPose(const PosedFrame& frame);
  Status saveMap(const std::string& path);

  ServerConfig config_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::atomic<bool> stop_requested_{false};
  bool stopped_ = false;  // stop() ran (main thread only)

  LabelLegend legend_;
  dds::Participant participant_;
  ServerState state_;
  FrameQueue frames_;
  std::unique_ptr<Mapper> mapper_;
  std::unique_ptr<FusionLoop> fusion_;
  std::unique_ptr<Ingest> ingest_;
  std::unique_ptr<RosIngest> ros_ingest_;                    // with --ros-ingest only
  std::unique_ptr<DistanceField> distance_field_;            // with --esdf only
  std::unique_ptr<OccupancyPublisher> occupancy_publisher_;  // with --esdf only
  std::unique_ptr<Services> services_;
  std::unique_ptr<MapperAccess> map_access_;         // what the map updates read
  std::unique_ptr<MapUpdatePublisher> map_updates_;  // null with --map-updates.rate 0

  dds::Topic<semfuse_msg_dds__TrackedPose_> pose_topic_;
  dds::Topic<semfuse_msg_dds__ServerStatus_> status_topic_;
  dds::Topic<semfuse_msg_dds__LabelLegend_> legend_topic_;
  dds::Writer<semfuse_msg_dds__TrackedPose_> pose_writer_;
  dds::Writer<semfuse_msg_dds__ServerStatus_> status_writer_;
  dds::Writer<semfuse_msg_dds__LabelLegend_> legend_writer_;

  mutable std::mutex save_mutex_;  // one save at a time (autosave, admin, shutdown)
  bool last_save_ok_ = true;
  std::chrono::steady_clock::time_point last_save_{};
  bool saved_once_ = false;
};

}  // namespace semfuse::server
