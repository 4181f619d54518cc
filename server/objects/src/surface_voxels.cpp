#include "semfuse/objects/surface_voxels.hpp"

#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "leaf_scanner.hpp"

namespace semfuse::objects {
namespace {

using detail::GeometryLeaf;
using IndexLeaf = openvdb::Int32Tree::LeafNodeType;
using detail::kLeafDim;

}  // namespace

SurfaceVoxels::SurfaceVoxels(double voxel_size, std::vector<SurfaceVoxel> voxels)
    : voxel_size_(voxel_size), voxels_(std::move(voxels)), index_(std::make_shared<openvdb::Int32Tree>(kNone)) {
  // Leaves first (serially: OpenVDB trees do not grow concurrently), then their values in parallel.
  std::vector<std::pair<IndexLeaf*, std::size_t>> starts;  // a leaf and the first of its voxels
  for (std::size_t i = 0; i < voxels_.size(); ++i) {
    const openvdb::Coord origin = voxels_[i].ijk & ~(kLeafDim - 1);
    if (starts.empty() || starts.back().first->origin() != origin) starts.emplace_back(index_->touchLeaf(origin), i);
  }
  tbb::parallel_for(std::size_t{0}, starts.size(), [&](std::size_t s) {
    IndexLeaf& leaf = *starts[s].first;
    const std::size_t end = s + 1 < starts.size() ? starts[s + 1].second : voxels_.size();
    for (std::size_t i = starts[s].second; i < end; ++i)
      leaf.setValueOn(IndexLeaf::coordToOffset(voxels_[i].ijk), static_cast<int32_t>(i));
  });
}

bool SurfaceVoxels::instancesSeenApart(uint32_t a, uint32_t b) const {
  return volume::hasInstancePair(instances_apart_, a, b);
}

Eigen::Vector3d SurfaceVoxels::position(std::size_t i) const {
  const openvdb::Coord& c = voxels_[i].ijk;
  return Eigen::Vector3d(c.x(), c.y(), c.z()) * voxel_size_;
}

SurfaceVoxels extractSurface(const volume::LabeledVolume& volume, const LabelLegend& legend,
                             int min_instance_evidence) {
  const auto& tree = volume.geometryGrid().tree();
  std::vector<const GeometryLeaf*> leaves;
  leaves.reserve(tree.leafCount());
  tree.getNodes(leaves);
  const detail::CountedLabels counted(legend);
  std::vector<std::vector<SurfaceVoxel>> per_leaf(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 32),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      detail::LeafScanner scanner(volume, counted, min_instance_evidence);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) scanner.scan(*leaves[i], per_leaf[i]);
                    });
  std::size_t total = 0;
  for (const auto& leaf : per_leaf) total += leaf.size();
  std::vector<SurfaceVoxel> voxels;
  voxels.reserve(total);
  for (const auto& leaf : per_leaf) voxels.insert(voxels.end(), leaf.begin(), leaf.end());
  SurfaceVoxels surface(volume.voxelSize(), std::move(voxels));
  surface.setInstancePairsSeenApart(volume.instancePairsSeenApart());
  return surface;
}

}  // namespace semfuse::objects
