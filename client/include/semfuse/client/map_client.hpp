#pragma once
// MapClient: every query of the map server as one blocking call with a timeout, plus the
// server's latest status and label legend (transient-local topics: a new client gets them at once).
//
//   semfuse::dds::Participant participant;
//   semfuse::client::MapClient map(participant);
//   auto view = map.raycast(pose, intrinsics, semfuse::client::kAllLayers, std::chrono::seconds(5));
//   if (!view) std::cerr << view.error() << "\n";
//   else cv::imwrite("depth.exr", view.value().depth);
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "semfuse/client/call_result.hpp"
#include "semfuse/client/server_status.hpp"
#include "semfuse/core/distance_service_types.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/object_events.hpp"
#include "semfuse/core/raycast_layers.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::client {

using Timeout = std::chrono::milliseconds;

// The services' requests and answers (semfuse/core/service_types.hpp) and the raycast layer
// bits (semfuse/core/raycast_layers.hpp), as the client library names them.
using semfuse::Box;
using semfuse::kAllLayers;
using semfuse::kColorLayer;
using semfuse::kConfidenceLayer;
using semfuse::kDepthLayer;
using semfuse::kLabelsLayer;
using semfuse::kNormalsLayer;
using semfuse::LabelArea;
using semfuse::ObjectInstance;
using semfuse::ObjectsRequest;
using semfuse::RaycastImages;
using semfuse::RaycastLayer;
using semfuse::RaycastLayers;
using semfuse::RegionSummary;
using semfuse::VoxelSample;
// The distance field's (semfuse/core/distance_service_types.hpp).
using semfuse::DistanceSample;
using semfuse::OccupancyGrid;
using semfuse::OccupancySliceRequest;
using semfuse::Segment;
using semfuse::SegmentResult;
using semfuse::SegmentStatus;
using semfuse::SemanticSample;
using semfuse::SemanticSlice;
using semfuse::SemanticSliceRequest;

// A whole mesh, put together from the chunks of the mesh service.
struct MeshData {
  std::vector<uint8_t> ply;  // a complete PLY file
  uint32_t vertex_count = 0;
  uint32_t face_count = 0;
};

class MapClient {
 public:
  explicit MapClient(const dds::Participant& participant);
  ~MapClient();
  MapClient(const MapClient&) = delete;
  MapClient& operator=(const MapClient&) = delete;

  CallResult<RaycastImages> raycast(const Pose& camera_to_world, const PinholeIntrinsics& intrinsics,
                                    RaycastLayers layers, Timeout timeout, float max_range = 0.0F);
  CallResult<std::vector<VoxelSample>> labelsAt(const std::vector<Eigen::Vector3d>& points, Timeout timeout);
  CallResult<RegionSummary> region(const Box& box, Timeout timeout);
  // label 0 = objects of every label.
  CallResult<std::vector<ObjectInstance>> objects(LabelId label, uint32_t min_voxels, Timeout timeout);
  // Every filter of the objects service: label, size, near a point, fragments.
  CallResult<std::vector<ObjectInstance>> objects(const ObjectsRequest& request, Timeout timeout);
  // Fetches every chunk of the mesh; `timeout` applies to each chunk's request. object_id != 0:
  // only that object's surface (an id of objects()).
  CallResult<MeshData> mesh(const std::optional<Box>& box, Timeout timeout, uint32_t object_id = 0);

  CallResult<ServerStatus> stats(Timeout timeout);
  // path "" = the server's own map file.
  CallResult<ServerStatus> save(const std::string& path, Timeout timeout);
  CallResult<ServerStatus> load(const std::string& path, Timeout timeout);
  CallResult<ServerStatus> reset(Timeout timeout);

  // The newest status / legend received so far (nullopt before the first one). The wait
  // variants block up to `timeout` for the first one.
  std::optional<ServerStatus> latestStatus();
  std::optional<LabelLegend> latestLegend();
  std::optional<ServerStatus> waitForStatus(Timeout timeout);
  std::optional<LabelLegend> waitForLegend(Timeout timeout);

  // The poses the server publishes for every frame it processes (rt/semfuse/poses): where each
  // camera was when its frame was integrated, or that its tracking was lost. The client listens
  // from its construction on; takePoses() returns what arrived since the last call, waiting up to
  // `timeout` for the first when none is waiting. Poses that fail to decode are left out and
  // counted in rejectedPoses().
  std::vector<TrackedPose> takePoses(Timeout timeout);
  uint64_t rejectedPoses() const;

  // How the map's objects changed (rt/semfuse/object_events): one ObjectEvents per update of the
  // objects that changed something (objects appeared, merged, split or vanished; the server
  // regroups the objects when a client asks for them). The first call subscribes, and gets the
  // server's last 16 updates; each call returns what arrived since the last one, waiting up to
  // `timeout` for the first when none is waiting. Updates that fail to decode are left out and
  // counted in rejectedObjectEvents().
  std::vector<ObjectEvents> takeObjectEvents(Timeout timeout);
  uint64_t rejectedObjectEvents() const;

  // The distance field, for planners and navigation (servers started with --esdf; others answer
  // UNAVAILABLE). Distances in metres, world frame, z up; unknown space is reported as unknown.
  // Signed distance and its unit gradient at points (thousands per call).
  CallResult<std::vector<DistanceSample>> distances(const std::vector<Eigen::Vector3d>& points, Timeout timeout);
  // A 2D occupancy grid (nav_msgs/OccupancyGrid's layout) of a height band.
  CallResult<OccupancyGrid> occupancySlice(const OccupancySliceRequest& request, Timeout timeout);
  // Distance and direction to the nearest surface of any of `labels`.
  CallResult<std::vector<SemanticSample>> semanticDistances(const std::vector<LabelId>& labels,
                                                            const std::vector<Eigen::Vector3d>& points,
                                                            Timeout timeout);
  // That distance over a horizontal plane.
  CallResult<SemanticSlice> semanticSlice(const SemanticSliceRequest& request, Timeout timeout);
  // Whether a sphere of `radius` (0: a point) moved along each segment stays clear.
  CallResult<std::vector<SegmentResult>> checkSegments(const std::vector<Segment>& segments, double radius,
                                                       Timeout timeout);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  struct DistanceRpcs;  // map_client_distance.cpp
  struct DistanceRpcsDeleter {
    void operator()(DistanceRpcs* rpcs) const;
  };
  std::unique_ptr<DistanceRpcs, DistanceRpcsDeleter> distance_;
  static std::unique_ptr<DistanceRpcs, DistanceRpcsDeleter> makeDistanceRpcs(const dds::Participant& participant);
};

}  // namespace semfuse::client
