#pragma once
// Internal: the scan that finds one leaf's surface voxels (surface_voxels.hpp says which voxels
// those are), shared by extractSurface() and SurfaceCache.
#include <cstdint>
#include <memory>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/objects/surface_voxels.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::objects::detail {

using GeometryLeaf = volume::GeometryGrid::TreeType::LeafNodeType;
inline constexpr int kLeafDim = static_cast<int>(GeometryLeaf::DIM);  // voxels per leaf side

// Which labels make objects: not unlabeled, not background. A table over every label id, so that
// the scan's test per voxel is one read.
class CountedLabels {
 public:
  explicit CountedLabels(const LabelLegend& legend);
  bool operator()(LabelId label) const { return counted_[label] != 0; }

 private:
  std::vector<uint8_t> counted_;
};

// Scans leaves of one volume; holds the scratch space of one thread.
class LeafScanner {
 public:
  LeafScanner(const volume::LabeledVolume& volume, const CountedLabels& counted, int min_instance_evidence);
  ~LeafScanner();
  LeafScanner(const LeafScanner&) = delete;
  LeafScanner& operator=(const LeafScanner&) = delete;

  // Appends the leaf's surface voxels to `out`, in the order of the voxels in the leaf. The leaf's
  // six face neighbours are read too (the TSDF one voxel across).
  void scan(const GeometryLeaf& leaf, std::vector<SurfaceVoxel>& out);

 private:
  class Brick;
  const volume::GeometryGrid::TreeType& tree_;
  const volume::InstanceGrid::TreeType* instances_;
  const CountedLabels& counted_;
  int min_instance_evidence_;
  float face_area_;
  std::unique_ptr<Brick> brick_;
};

}  // namespace semfuse::objects::detail
