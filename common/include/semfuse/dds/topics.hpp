#pragma once
// Topic names of the wire contract (idl/README.md), in ROS 2's DDS naming: message
// topics are "rt/<ros name>", a service /x/y is the pair "rq/x/yRequest" and "rr/x/yReply".
#include <string>
#include <string_view>

namespace semfuse::dds::topics {

inline constexpr const char* kFrames = "rt/semfuse/frames";
inline constexpr const char* kSegmentations = "rt/semfuse/segmentations";
inline constexpr const char* kPoses = "rt/semfuse/poses";
inline constexpr const char* kStatus = "rt/semfuse/status";
inline constexpr const char* kLabels = "rt/semfuse/labels";
inline constexpr const char* kMapUpdates = "rt/semfuse/map_updates";      // semfuse MapUpdate
inline constexpr const char* kMapMarkers = "rt/semfuse/map_markers";      // visualization_msgs/MarkerArray
inline constexpr const char* kMapCloud = "rt/semfuse/map_cloud";          // sensor_msgs/PointCloud2
inline constexpr const char* kOccupancy = "rt/semfuse/occupancy";         // nav_msgs/OccupancyGrid
inline constexpr const char* kObjectEvents = "rt/semfuse/object_events";  // semfuse ObjectEvents

struct ServiceTopics {
  std::string request;
  std::string reply;
};

// The topic pair of ROS 2 service "/<ns>/<name>"; ns may be empty.
inline ServiceTopics service(std::string_view name, std::string_view ns = "semfuse") {
  std::string base = ns.empty() ? std::string(name) : std::string(ns) + "/" + std::string(name);
  return {"rq/" + base + "Request", "rr/" + base + "Reply"};
}

inline ServiceTopics raycast() { return service("raycast"); }
inline ServiceTopics labelsAt() { return service("labels_at"); }
inline ServiceTopics region() { return service("region"); }
inline ServiceTopics objects() { return service("objects"); }
inline ServiceTopics mesh() { return service("mesh"); }
inline ServiceTopics admin() { return service("admin"); }
inline ServiceTopics mapBlocks() { return service("map_blocks"); }
inline ServiceTopics distance() { return service("distance"); }
inline ServiceTopics occupancySlice() { return service("occupancy_slice"); }
inline ServiceTopics semanticDistance() { return service("semantic_distance"); }
inline ServiceTopics semanticSlice() { return service("semantic_slice"); }
inline ServiceTopics segmentCheck() { return service("segment_check"); }

}  // namespace semfuse::dds::topics
