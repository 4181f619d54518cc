#pragma once
// The labeled surface of a volume as a list of voxels: what objects are made of.
//
// A surface voxel is an observed, labeled voxel (not unlabeled, not a background label) that owns
// a zero crossing of the TSDF: of two observed neighbours along an axis whose TSDF changes sign,
// the one nearer to zero owns the crossing (the outside one on a tie). So every crossing has one
// voxel, wherever the surface lies between two voxel centres: a test such as |tsdf| < half a voxel
// finds no voxel at all where a plane lies half way between two layers.
//
// Each carries its normal (the TSDF gradient by central differences), its share of the surface
// area (a crossing along axis a stands for voxel^2 * |n_a| of surface, which sums to the area of
// a plane whatever its orientation), its label, label score and panoptic instance.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/core/legend.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::objects {

struct SurfaceVoxel {
  openvdb::Coord ijk;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // unit, towards free space; zero where undefined
  float area_m2 = 0.0f;
  float score = 0.0f;
  LabelId label = kUnlabeled;
  uint32_t instance = 0;  // the panoptic instance its evidence names (0 = none or too little)
};

class SurfaceVoxels {
 public:
  // Index tree value where a voxel is not on the surface.
  static constexpr int32_t kNone = -1;

  SurfaceVoxels(double voxel_size, std::vector<SurfaceVoxel> voxels);

  const std::vector<SurfaceVoxel>& voxels() const { return voxels_; }
  std::size_t size() const { return voxels_.size(); }
  const SurfaceVoxel& operator[](std::size_t i) const { return voxels_[i]; }
  double voxelSize() const { return voxel_size_; }
  Eigen::Vector3d position(std::size_t i) const;  // world, metres

  // The index of each surface voxel at its coordinate (kNone elsewhere): neighbour lookups.
  const openvdb::Int32Tree& indexTree() const { return *index_; }
  int32_t find(const openvdb::Coord& ijk) const { return index_->getValue(ijk); }

  // Two objects: instances a segmentation named as two of its segments
  // (LabeledVolume::instancesSeenApart), as the map had them.
  bool instancesSeenApart(uint32_t a, uint32_t b) const;
  void setInstancePairsSeenApart(std::vector<uint64_t> sorted_keys) { instances_apart_ = std::move(sorted_keys); }

 private:
  double voxel_size_;
  std::vector<SurfaceVoxel> voxels_;
  std::vector<uint64_t> instances_apart_;
  openvdb::Int32Tree::Ptr index_;
};

// In parallel over the volume's leaves; the order is the leaves' and, inside a leaf, the voxels'.
// Instances come from the volume's instance evidence when it has any (volume/instance_evidence.hpp)
// and count from min_instance_evidence observations on.
SurfaceVoxels extractSurface(const volume::LabeledVolume& volume, const LabelLegend& legend,
                             int min_instance_evidence = 2);

}  // namespace semfuse::objects
