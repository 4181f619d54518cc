#pragma once
// What an object's surface voxels tell about it: size, area, where it is, how it lies.
//
// The oriented box is upright when up is known: its third axis is up, the other two those of the
// smallest rectangle around the object's footprint (rotating calipers over the convex hull of its
// voxels projected on the floor plane), which is how furniture stands. Without up its axes are the
// principal axes of the voxels. Boxes and extents reach half a voxel beyond the outer voxel centres.
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/objects/grouping.hpp"
#include "semfuse/objects/surface_voxels.hpp"

namespace semfuse::objects {

struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // along the axes
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();      // columns: unit axes, right-handed
};

struct ObjectFigures {
  uint64_t voxel_count = 0;
  double area_m2 = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // mean of the voxel centres
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();  // axis-aligned
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
  OrientedBox box;
  float mean_confidence = 0.0f;        // mean label score of the voxels
  std::vector<openvdb::Coord> leaves;  // origins of the 8^3 leaves its voxels lie in, sorted
};

// Per group of the grouping, in parallel over groups.
std::vector<ObjectFigures> measureGroups(const SurfaceVoxels& surface, const Grouping& grouping,
                                         const Eigen::Vector3d& up);

// The smallest-area rectangle around 2D points: centre, half extents and the direction of its
// first axis (unit). Exposed for tests.
struct Rectangle2d {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d half_extents = Eigen::Vector2d::Zero();
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();
};
Rectangle2d minimumAreaRectangle(std::vector<Eigen::Vector2d> points);

}  // namespace semfuse::objects
