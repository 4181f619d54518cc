#pragma once
// Queries of the distance field (esdf_map.hpp), as free functions. All distances are metres in the
// world frame; each function only reads the map (call it under the lock that holds off apply()).
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "semfuse/esdf/esdf_map.hpp"

namespace semfuse::esdf {

// Signed distance at a point: negative inside obstacles; the gradient is its unit gradient (it
// points away from the nearest surface in free space, towards it inside), so a planner climbs it
// to gain clearance. Trilinear between the 8 voxels around the point where all are observed;
// where some are not, the nearest voxel's distance and the direction from its site. Unknown
// where the nearest voxel was never observed. beyond: no surface within the maximum distance
// (distance is then the maximum).
struct DistanceSample {
  bool known = false;
  bool beyond = false;
  float distance = 0.0F;
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
};
std::vector<DistanceSample> distancesAt(const EsdfMap& map, const std::vector<Eigen::Vector3d>& points);

// A 2D occupancy grid from a horizontal band of the field, one cell per voxel column, laid out as
// nav_msgs/OccupancyGrid: cells[y * width + x], cell (0, 0) at the minimum corner `origin`.
// A cell is occupied (100) when a voxel of its column within [z_min, z_max] lies inside an
// obstacle or within half a voxel of its surface, free (0) when every voxel of the column in the
// band is observed and clear, unknown (-1) otherwise. Free cells within inflation_radius of an
// occupied cell (2D Euclidean distance between cell centres) are 99.
inline constexpr int8_t kCellFree = 0;
inline constexpr int8_t kCellInflated = 99;
inline constexpr int8_t kCellOccupied = 100;
inline constexpr int8_t kCellUnknown = -1;

struct SliceBounds {
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
};
struct OccupancyRequest {
  double z_min = 0.1, z_max = 1.0;
  std::optional<SliceBounds> bounds;  // none: the field's observed extent
  double inflation_radius = 0.0;
};
struct OccupancyGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // world x, y of cell (0, 0)'s minimum corner
  double resolution = 0.0;                           // metres per cell (the voxel size)
  double z_min = 0.0, z_max = 0.0;                   // the band the cells summarise
  int width = 0, height = 0;
  std::vector<int8_t> cells;
};
// The number of cells a request covers (for limits), 0 for an empty map.
uint64_t occupancyCellCount(const EsdfMap& map, const OccupancyRequest& request);
// Assumes a valid request (z_min <= z_max, bounds min <= max, inflation >= 0: the caller checks).
OccupancyGrid occupancySlice(const EsdfMap& map, const OccupancyRequest& request);

// Whether a sphere of `radius` (0: a point) moved along straight segments stays clear of
// obstacles: sphere tracing on the field, stepping by the clearance (less one voxel for the
// field's error) and at least half a voxel. The first sample closer than the radius makes it a
// collision, the first unobserved one unknown, whichever comes first along the segment.
enum class SegmentStatus : uint8_t { kFree = 0, kCollision = 1, kUnknown = 2 };
struct Segment {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
};
struct SegmentResult {
  SegmentStatus status = SegmentStatus::kFree;
  float fraction = 1.0F;  // where along the segment (0 = start) it first failed; 1 when free
  Eigen::Vector3d blocked_at = Eigen::Vector3d::Zero();
  float min_clearance = 0.0F;  // smallest distance minus radius over the samples taken
};
std::vector<SegmentResult> checkSegments(const EsdfMap& map, const std::vector<Segment>& segments, double radius);

}  // namespace semfuse::esdf
