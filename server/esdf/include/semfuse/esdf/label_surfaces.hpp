#pragma once
// The labeled surface of the map as points, kept per leaf by the distance field's update: for
// every surface site on the free side of a surface (0 <= tsdf < one voxel) that carries a label,
// the surface point under it (the site moved by its tsdf against the TSDF's gradient, so the point
// lies on the zero crossing, not on the voxel centre). Semantic distance queries gather the
// points of the labels they ask for from the leaves that hold any (semantic_distance.hpp).
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/core/legend.hpp"

namespace semfuse::esdf {

struct SurfacePoint {
  Eigen::Vector3f position;  // world, metres
  LabelId label = kUnlabeled;
};

class LabelSurfaces {
 public:
  // Replaces the points of the leaf at `origin` (empty: the leaf holds none).
  void setLeaf(const openvdb::Coord& origin, std::vector<SurfacePoint> points);
  void clear();

  // Every point whose label is one of `labels` (sorted or not; duplicates are harmless).
  std::vector<SurfacePoint> gather(const std::vector<LabelId>& labels) const;

  // Bumped by every change: a cache of gathered points is valid while it stays the same.
  uint64_t revision() const { return revision_; }
  std::size_t memoryBytes() const;

 private:
  struct KeyHash {
    std::size_t operator()(const openvdb::Coord& c) const {
      return static_cast<std::size_t>((uint64_t(uint32_t(c.x())) * 73856093u) ^
                                      (uint64_t(uint32_t(c.y())) * 19349663u) ^
                                      (uint64_t(uint32_t(c.z())) * 83492791u));
    }
  };
  std::unordered_map<openvdb::Coord, std::vector<SurfacePoint>, KeyHash> by_leaf_;
  // label -> leaves holding points of it, with how many
  std::unordered_map<LabelId, std::unordered_map<openvdb::Coord, uint32_t, KeyHash>> leaves_of_label_;
  std::size_t points_ = 0;
  uint64_t revision_ = 0;
};

}  // namespace semfuse::esdf
