#pragma once
// The distance field's services (distance, occupancy_slice, semantic_distance, semantic_slice,
// segment_check; idl/semfuse/srv.idl) as plain C++ values, beside service_types.hpp's. The
// server's handlers and the client library work with these; common/wire's distance codecs turn
// them into the generated wire structs and back. Metres, world frame, z up.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse {

// distance: the signed distance field at points.
struct DistanceRequest {
  std::vector<Eigen::Vector3d> points;
};
struct DistanceSample {
  bool known = false;     // false: nobody observed the point (distance and gradient mean nothing)
  bool beyond = false;    // no surface within the server's maximum distance; distance is that maximum
  float distance = 0.0F;  // negative inside obstacles
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();  // unit; away from the nearest surface in free space
};

// occupancy_slice: a 2D grid from a height band (nav_msgs/OccupancyGrid).
struct OccupancySliceRequest {
  double z_min = 0.1;
  double z_max = 1.0;
  bool use_bounds = false;  // false: the whole observed extent
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
  double inflation_radius = 0.0;
};
// Cell values as nav_msgs/OccupancyGrid holds them.
inline constexpr int8_t kOccupancyFree = 0;
inline constexpr int8_t kOccupancyInflated = 99;  // free, but within the inflation radius of an obstacle
inline constexpr int8_t kOccupancyOccupied = 100;
inline constexpr int8_t kOccupancyUnknown = -1;
struct OccupancyGrid {
  std::string frame_id = "map";
  Stamp stamp;
  double resolution = 0.0;  // metres per cell
  uint32_t width = 0, height = 0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // world x, y of cell (0, 0)'s minimum corner
  double z = 0.0;                                    // height of the grid's plane (the band's middle)
  std::vector<int8_t> cells;                         // cells[y * width + x]
};

// semantic_distance: the nearest surface of any of `labels`.
struct SemanticDistanceRequest {
  std::vector<LabelId> labels;
  std::vector<Eigen::Vector3d> points;
};
struct SemanticSample {
  bool found = false;  // false: the map holds no surface of those labels
  LabelId label = kUnlabeled;
  float distance = 0.0F;
  Eigen::Vector3f direction = Eigen::Vector3f::Zero();  // unit, from the point towards surface_point
  Eigen::Vector3d surface_point = Eigen::Vector3d::Zero();
};

// semantic_slice: that distance over a horizontal plane.
struct SemanticSliceRequest {
  std::vector<LabelId> labels;
  double z = 0.0;
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
  double resolution = 0.05;
};
struct SemanticSlice {
  Eigen::Vector2d min = Eigen::Vector2d::Zero();  // cell (0, 0)'s minimum corner
  double resolution = 0.0;
  double z = 0.0;
  cv::Mat distance;  // CV_32FC1 metres, row 0 at min.y(); +infinity where no surface of the labels exists
};

// segment_check: swept spheres along segments.
struct Segment {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
};
struct SegmentCheckRequest {
  std::vector<Segment> segments;
  double radius = 0.0;
};
enum class SegmentStatus : uint8_t { kFree = 0, kCollision = 1, kUnknown = 2 };
struct SegmentResult {
  SegmentStatus status = SegmentStatus::kFree;
  float fraction = 1.0F;  // where along the segment it first failed (0 = start); 1 when free
  Eigen::Vector3d blocked_at = Eigen::Vector3d::Zero();
  float min_clearance = 0.0F;  // smallest distance minus radius seen along it
};

}  // namespace semfuse
