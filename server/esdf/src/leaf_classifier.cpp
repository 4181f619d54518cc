#include "leaf_classifier.hpp"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "semfuse/volume/voxel.hpp"

namespace semfuse::esdf::detail {

LeafClassifier::LeafClassifier(double voxel_size, const EsdfParams& params)
    : voxel_(static_cast<float>(voxel_size)), min_weight_(params.min_site_weight) {}

bool LeafClassifier::classify(const ChangedLeaf& leaf,
                              std::array<Classified, volume::LabeledVolume::kLeafVoxels>& out) {
  constexpr float kUnobserved = std::numeric_limits<float>::quiet_NaN();
  tsdf_.fill(kUnobserved);
  if (leaf.has_geometry) {
    for (int x = 0, n = 0; x < kDim; ++x)
      for (int y = 0; y < kDim; ++y)
        for (int z = 0; z < kDim; ++z, ++n)
          if (leaf.observed[n]) tsdf_[padded(x, y, z)] = volume::unpackTsdf(leaf.voxels[n]);
    ChangedLeaf::forEachHaloVoxel([&](int i, int x, int y, int z) { tsdf_[padded(x, y, z)] = leaf.halo[i]; });
  }
  bool any_known = false;
  for (int x = 0, n = 0; x < kDim; ++x)
    for (int y = 0; y < kDim; ++y)
      for (int z = 0; z < kDim; ++z, ++n) {
        Classified c;
        const float tsdf = tsdf_[padded(x, y, z)];
        if (!std::isnan(tsdf)) {
          c.known = true;
          c.inside = tsdf < 0.0f;
          if (volume::unpackWeight(leaf.voxels[n]) >= min_weight_) {
            const Crossing crossing = nearestCrossing(x, y, z);
            c.site = crossing.axis >= 0;
            c.site_distance = static_cast<uint8_t>(std::lround(crossing.distance * 255.0f));
          }
        } else if (leaf.observed_free[n]) {
          c.known = true;
        }
        any_known |= c.known;
        out[n] = c;
      }
  return any_known;
}

std::vector<SurfacePoint> LeafClassifier::surfacePoints(const ChangedLeaf& leaf) const {
  std::vector<SurfacePoint> points;
  if (!leaf.has_geometry) return points;
  for (int x = 0, n = 0; x < kDim; ++x)
    for (int y = 0; y < kDim; ++y)
      for (int z = 0; z < kDim; ++z, ++n) {
        if (!leaf.observed[n]) continue;
        const volume::PackedVoxel v = leaf.voxels[n];
        const LabelId label = volume::unpackLabel(v);
        if (label == kUnlabeled || tsdf_[padded(x, y, z)] < 0.0f || volume::unpackWeight(v) < min_weight_) continue;
        const Crossing crossing = nearestCrossing(x, y, z);
        if (crossing.axis < 0) continue;
        const openvdb::Coord ijk = leaf.origin.offsetBy(x, y, z);
        Eigen::Vector3f position(ijk.x() * voxel_, ijk.y() * voxel_, ijk.z() * voxel_);
        position[crossing.axis] += static_cast<float>(crossing.direction) * crossing.fraction * voxel_;
        points.push_back({position, label});
      }
  return points;
}

void ClassifiedLeaves::classify(const std::vector<ChangedLeaf>& changed, double voxel_size, const EsdfParams& params) {
  leaves.resize(changed.size());
  // Leaves in chunks of 16: a classifier's padded array is set up once per task.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      LeafClassifier classifier(voxel_size, params);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        ClassifiedLeaf& out = leaves[i];
                        out.any_known = classifier.classify(changed[i], out.voxels);
                        out.surface = classifier.surfacePoints(changed[i]);
                      }
                    });
}

LeafClassifier::Crossing LeafClassifier::nearestCrossing(int x, int y, int z) const {
  const int centre = padded(x, y, z);
  const float tsdf = tsdf_[centre];
  const bool negative = tsdf < 0.0f;
  // Steps between neighbours in tsdf_ along x, y, z.
  constexpr int kStride[3] = {kPadded * kPadded, kPadded, 1};
  float fraction[3] = {0.0f, 0.0f, 0.0f};
  bool crosses[3] = {false, false, false};
  Crossing best;
  for (int axis = 0; axis < 3; ++axis)
    for (int step : {-1, 1}) {
      const float other = tsdf_[centre + step * kStride[axis]];
      // An unobserved neighbour (NaN) compares false both ways: no crossing.
      if (!(negative ? other >= 0.0f : other < 0.0f)) continue;
      const float f = std::abs(tsdf) / (std::abs(tsdf) + std::abs(other));
      if (!crosses[axis] || f < fraction[axis]) fraction[axis] = f, crosses[axis] = true;
      if (best.axis < 0 || f < best.fraction) best = {axis, step, f, f};
    }
  if (best.axis < 0 || best.fraction <= 0.0f) return best;  // none, or the surface passes through the centre
  float inverse_squares = 0.0f;
  for (int axis = 0; axis < 3; ++axis)
    if (crosses[axis]) inverse_squares += 1.0f / (fraction[axis] * fraction[axis]);
  best.distance = 1.0f / std::sqrt(inverse_squares);
  return best;
}

}  // namespace semfuse::esdf::detail
