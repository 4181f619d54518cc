#include "semfuse/objects/surface_voxels.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace semfuse::objects {
namespace {

using GeometryLeaf = volume::GeometryGrid::TreeType::LeafNodeType;
using IndexLeaf = openvdb::Int32Tree::LeafNodeType;
constexpr int kDim = static_cast<int>(GeometryLeaf::DIM);

// A leaf's TSDF with a one-voxel rim from its six face neighbours, so that every lookup of the
// scan is an array read. NaN marks an unobserved voxel.
class Brick {
 public:
  static constexpr int kSide = kDim + 2;

  void load(const volume::GeometryGrid::TreeType& tree, const GeometryLeaf& leaf) {
    values_.fill(std::numeric_limits<float>::quiet_NaN());
    for (openvdb::Index n = 0; n < GeometryLeaf::SIZE; ++n) {
      const volume::PackedVoxel v = leaf.getValue(n);
      if (volume::isObserved(v)) at(int(n >> 6), int((n >> 3) & 7), int(n & 7)) = volume::unpackTsdf(v);
    }
    const openvdb::Coord origin = leaf.origin();
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {-1, 1}) {
        openvdb::Coord neighbour_origin = origin;
        neighbour_origin[axis] += side * kDim;
        const GeometryLeaf* neighbour = tree.probeConstLeaf(neighbour_origin);
        if (!neighbour) continue;
        const int from = side < 0 ? kDim - 1 : 0;  // the neighbour's layer that touches this leaf
        const int to = side < 0 ? -1 : kDim;
        for (int a = 0; a < kDim; ++a)
          for (int b = 0; b < kDim; ++b) {
            std::array<int, 3> src{}, dst{};
            src[axis] = from;
            dst[axis] = to;
            src[(axis + 1) % 3] = dst[(axis + 1) % 3] = a;
            src[(axis + 2) % 3] = dst[(axis + 2) % 3] = b;
            const volume::PackedVoxel v =
                neighbour->getValue(GeometryLeaf::coordToOffset(openvdb::Coord(src[0], src[1], src[2])));
            if (volume::isObserved(v)) at(dst[0], dst[1], dst[2]) = volume::unpackTsdf(v);
          }
      }
  }
  // Local coordinates from -1 to kDim.
  float operator()(int x, int y, int z) const { return values_[index(x, y, z)]; }

 private:
  static int index(int x, int y, int z) { return (x + 1) + kSide * ((y + 1) + kSide * (z + 1)); }
  float& at(int x, int y, int z) { return values_[index(x, y, z)]; }
  std::array<float, kSide * kSide * kSide> values_;
};

// Central difference where both neighbours are observed, one-sided where one is, 0 otherwise.
float derivative(float minus, float centre, float plus) {
  const bool has_minus = !std::isnan(minus), has_plus = !std::isnan(plus);
  if (has_minus && has_plus) return 0.5f * (plus - minus);
  if (has_plus) return plus - centre;
  if (has_minus) return centre - minus;
  return 0.0f;
}

struct LeafSurface {
  std::vector<SurfaceVoxel> voxels;
};

LeafSurface scanLeaf(const volume::GeometryGrid::TreeType& tree, const GeometryLeaf& leaf, const LabelLegend& legend,
                     const volume::InstanceGrid::TreeType* instances, int min_instance_evidence, double voxel_size,
                     Brick& brick) {
  LeafSurface out;
  bool loaded = false;
  const float face_area = static_cast<float>(voxel_size * voxel_size);
  const auto* instance_leaf = instances ? instances->probeConstLeaf(leaf.origin()) : nullptr;
  for (auto it = leaf.cbeginValueOn(); it; ++it) {
    const volume::PackedVoxel packed = *it;
    const LabelId label = volume::unpackLabel(packed);
    if (label == kUnlabeled || legend.isBackground(label) || !volume::isObserved(packed)) continue;
    if (!loaded) {
      brick.load(tree, leaf);
      loaded = true;
    }
    const openvdb::Index n = it.pos();
    const int x = int(n >> 6), y = int((n >> 3) & 7), z = int(n & 7);
    const float t = brick(x, y, z);
    const std::array<float, 3> minus{brick(x - 1, y, z), brick(x, y - 1, z), brick(x, y, z - 1)};
    const std::array<float, 3> plus{brick(x + 1, y, z), brick(x, y + 1, z), brick(x, y, z + 1)};
    // Which crossings along each axis this voxel owns (0, 1 or 2).
    std::array<int, 3> owned{0, 0, 0};
    bool owns_any = false;
    for (int axis = 0; axis < 3; ++axis)
      for (float other : {minus[axis], plus[axis]}) {
        if (std::isnan(other) || (t < 0.0f) == (other < 0.0f)) continue;
        const float mine = std::abs(t), theirs = std::abs(other);
        if (mine < theirs || (mine == theirs && t >= 0.0f)) {
          ++owned[axis];
          owns_any = true;
        }
      }
    if (!owns_any) continue;
    Eigen::Vector3f gradient(derivative(minus[0], t, plus[0]), derivative(minus[1], t, plus[1]),
                             derivative(minus[2], t, plus[2]));
    SurfaceVoxel voxel;
    voxel.ijk = it.getCoord();
    const float norm = gradient.norm();
    if (norm > 0.0f) voxel.normal = gradient / norm;
    for (int axis = 0; axis < 3; ++axis)
      // Without a gradient, a crossing counts as the mean over orientations (1/sqrt(3)).
      voxel.area_m2 += owned[axis] * face_area * (norm > 0.0f ? std::abs(voxel.normal[axis]) : 0.57735f);
    voxel.label = label;
    voxel.score = volume::unpackScore(packed);
    if (instance_leaf) {
      const volume::PackedInstance evidence = instance_leaf->getValue(n);
      if (static_cast<int>(volume::instanceEvidenceOf(evidence)) >= min_instance_evidence)
        voxel.instance = volume::instanceIdOf(evidence);
    }
    out.voxels.push_back(voxel);
  }
  return out;
}

}  // namespace

SurfaceVoxels::SurfaceVoxels(double voxel_size, std::vector<SurfaceVoxel> voxels)
    : voxel_size_(voxel_size), voxels_(std::move(voxels)), index_(std::make_shared<openvdb::Int32Tree>(kNone)) {
  // Leaves first (serially: OpenVDB trees do not grow concurrently), then their values in parallel.
  std::vector<std::pair<IndexLeaf*, std::size_t>> starts;  // a leaf and the first of its voxels
  for (std::size_t i = 0; i < voxels_.size(); ++i) {
    const openvdb::Coord origin = voxels_[i].ijk & ~(kDim - 1);
    if (starts.empty() || starts.back().first->origin() != origin) starts.emplace_back(index_->touchLeaf(origin), i);
  }
  tbb::parallel_for(std::size_t{0}, starts.size(), [&](std::size_t s) {
    IndexLeaf& leaf = *starts[s].first;
    const std::size_t end = s + 1 < starts.size() ? starts[s + 1].second : voxels_.size();
    for (std::size_t i = starts[s].second; i < end; ++i)
      leaf.setValueOn(IndexLeaf::coordToOffset(voxels_[i].ijk), static_cast<int32_t>(i));
  });
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
  const volume::InstanceGrid* instances = volume.instanceGrid();
  std::vector<LeafSurface> per_leaf(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 32),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      Brick brick;
                      for (std::size_t i = range.begin(); i != range.end(); ++i)
                        per_leaf[i] = scanLeaf(tree, *leaves[i], legend, instances ? &instances->tree() : nullptr,
                                               min_instance_evidence, volume.voxelSize(), brick);
                    });
  std::size_t total = 0;
  for (const LeafSurface& leaf : per_leaf) total += leaf.voxels.size();
  std::vector<SurfaceVoxel> voxels;
  voxels.reserve(total);
  for (LeafSurface& leaf : per_leaf) voxels.insert(voxels.end(), leaf.voxels.begin(), leaf.voxels.end());
  return SurfaceVoxels(volume.voxelSize(), std::move(voxels));
}

}  // namespace semfuse::objects
