#include "ray_marcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "semfuse/volume/cell_interpolation.hpp"

namespace semfuse::render::detail {
namespace {

using volume::PackedVoxel;
using LeafNode = volume::GeometryGrid::TreeType::LeafNodeType;

constexpr int kLeafMask = LeafNode::DIM - 1;

// Step as a fraction of the TSDF value in front of the surface. The stored TSDF is measured along
// the integrating cameras' rays, so it can exceed the true distance; stepping a little less than
// it keeps the next sample inside the negative band behind the surface instead of past it.
constexpr double kTsdfStepFraction = 0.8;
// Smallest step, in voxels: where the TSDF is unknown (some corner unobserved) or tiny.
constexpr double kMinStepVoxels = 0.5;
constexpr int kRefineIterations = 2;

// floor() for the index range of a grid; std::floor is a library call without SSE4.1, and it
// sits in the innermost loop.
int floorInt(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}
openvdb::Coord floorCoord(const Eigen::Vector3d& p) { return {floorInt(p.x()), floorInt(p.y()), floorInt(p.z())}; }

}  // namespace

RayMarcher::RayMarcher(const volume::LabeledVolume& volume)
    : accessor_(volume.geometryGrid().getConstAccessor()), inv_voxel_size_(1.0 / volume.voxelSize()) {}

bool RayMarcher::gatherCorners(const LeafView& view, const openvdb::Coord& base, PackedVoxel corners[8]) {
  // Most cells lie inside one leaf: read its buffer directly. Others cross into neighbouring
  // leaves, which the accessor's cache usually still holds.
  if (view.values && (base.x() & kLeafMask) != kLeafMask && (base.y() & kLeafMask) != kLeafMask &&
      (base.z() & kLeafMask) != kLeafMask) {
    const PackedVoxel* values = view.values + LeafNode::coordToOffset(base);
    for (int i = 0; i < 8; ++i) {
      corners[i] = values[volume::kCellCornerOffsets[i]];
      if (!volume::isObserved(corners[i])) return false;
    }
    return true;
  }
  for (int i = 0; i < 8; ++i) {
    corners[i] = accessor_.getValue(base.offsetBy(i & 1, (i >> 1) & 1, i >> 2));
    if (!volume::isObserved(corners[i])) return false;
  }
  return true;
}

bool RayMarcher::sampleAt(const LeafView& view, const openvdb::Coord& base, const Eigen::Vector3d& index,
                          float& tsdf_voxels) {
  PackedVoxel corners[8];
  if (!gatherCorners(view, base, corners)) return false;
  float v[8];
  for (int i = 0; i < 8; ++i) v[i] = volume::unpackTsdf(corners[i]);
  const auto fx = static_cast<float>(index.x() - base.x()), fy = static_cast<float>(index.y() - base.y()),
             fz = static_cast<float>(index.z() - base.z());
  tsdf_voxels = volume::trilinear(v, fx, fy, fz) * static_cast<float>(inv_voxel_size_);
  return true;
}

bool RayMarcher::sample(const Eigen::Vector3d& index, float& tsdf_voxels) {
  const openvdb::Coord base = floorCoord(index);
  LeafView view;
  enterLeaf(base, view);
  return sampleAt(view, base, index, tsdf_voxels);
}

bool RayMarcher::findSurface(const MarchRay& ray, double& t_surface) {
  // The ray in index space, once: t keeps its meaning (camera depth).
  const Eigen::Vector3d o = ray.origin * inv_voxel_size_;
  const Eigen::Vector3d d = ray.direction * inv_voxel_size_;
  const double voxels_per_t = d.norm();
  const double t_per_voxel = 1.0 / voxels_per_t;
  const double min_step = kMinStepVoxels * t_per_voxel;
  const double tsdf_step_scale = kTsdfStepFraction * t_per_voxel;

  bool have_positive = false;  // previous sample valid and in front of a surface
  double t_prev = 0.0;
  float f_prev = 0.0f;
  double t = ray.t_min;
  LeafView view;
  while (t < ray.t_max) {
    const Eigen::Vector3d x = o + t * d;
    const openvdb::Coord base = floorCoord(x);
    enterLeaf(base, view);
    float f;
    if (!sampleAt(view, base, x, f)) {
      have_positive = false;
      t += min_step;
      continue;
    }
    if (f <= 0.0f && have_positive) {
      // Regula falsi on the trilinear interpolant between the bracketing samples.
      double t_pos = t_prev, t_neg = t;
      float f_pos = f_prev, f_neg = f;
      auto secant = [&] { return t_pos + (t_neg - t_pos) * f_pos / static_cast<double>(f_pos - f_neg); };
      for (int i = 0; i < kRefineIterations && f_pos - f_neg > 0.0f; ++i) {
        const double t_mid = secant();
        float f_mid;
        if (!sample(o + t_mid * d, f_mid)) break;
        if (f_mid > 0.0f) {
          t_pos = t_mid;
          f_pos = f_mid;
        } else {
          t_neg = t_mid;
          f_neg = f_mid;
        }
      }
      t_surface = f_pos - f_neg > 0.0f ? secant() : t_neg;
      return true;
    }
    have_positive = f > 0.0f;
    t_prev = t;
    f_prev = f;
    t += f > 0.0f ? std::max(min_step, tsdf_step_scale * f) : min_step;
  }
  return false;
}

}  // namespace semfuse::render::detail
