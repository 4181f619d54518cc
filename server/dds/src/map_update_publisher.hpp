#pragma once
// MapUpdatePublisher: the live mesh on DDS. Owns the MapUpdater (server/core) and is its sink:
// every update part goes out on rt/semfuse/map_updates (semfuse MapUpdate), the same blocks as
// one TRIANGLE_LIST marker each on rt/semfuse/map_markers (visualization_msgs/MarkerArray, with a
// DELETEALL first when the map was cleared or replaced), and at most every
// --map-updates.cloud-period the whole surface on rt/semfuse/map_cloud (sensor_msgs/PointCloud2,
// transient-local). The ROS 2 messages are built only while a reader of them is matched; with no
// reader of any of the three the updater idles.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include <msg.h>
#include <sensor_msgs.h>
#include <visualization_msgs.h>

#include "map_access.hpp"
#include "map_update_config.hpp"
#include "map_updater.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/writer.hpp"
#include "semfuse/wire/ros_visualization.hpp"

namespace semfuse::server {

class MapUpdatePublisher final : public MapUpdater::Sink {
 public:
  // frame_id: the ROS 2 frame of the markers and the cloud (the server's --ros.world-frame).
  MapUpdatePublisher(const dds::Participant& participant, const MapAccess& map, const MapUpdateConfig& config,
                     const LabelLegend& legend, const std::string& frame_id);
  ~MapUpdatePublisher() override;

  void start() { updater_.start(); }
  void stop() { updater_.stop(); }
  MapUpdater& updater() { return updater_; }

  bool listening() const override;
  void publish(const MapUpdate& update) override;

 private:
  void publishMarkers(const MapUpdate& update);
  void publishCloud(const MapBlocksHeader& header);
  int32_t markerId(const BlockOrigin& origin);

  MapUpdateConfig config_;
  LabelLegend legend_;
  wire::VisualizationStyle style_;
  dds::Topic<semfuse_msg_dds__MapUpdate_> update_topic_;
  dds::Topic<visualization_msgs_msg_dds__MarkerArray_> marker_topic_;
  dds::Topic<sensor_msgs_msg_dds__PointCloud2_> cloud_topic_;
  dds::Writer<semfuse_msg_dds__MapUpdate_> update_writer_;
  dds::Writer<visualization_msgs_msg_dds__MarkerArray_> marker_writer_;
  dds::Writer<sensor_msgs_msg_dds__PointCloud2_> cloud_writer_;
  // The updater thread only:
  std::map<BlockOrigin, int32_t> marker_ids_;
  uint64_t marked_cleared_revision_ = 0;  // cleared_revision the markers last saw
  std::chrono::steady_clock::time_point last_cloud_{};
  uint64_t cloud_revision_ = ~0ull;
  // Last: its thread calls the members above and stops before they go.
  MapUpdater updater_;
};

}  // namespace semfuse::server
