#include "ray_marcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace semfuse::render::detail {
namespace {

using GeometryTree = volume::GeometryGrid::TreeType;
constexpr int kLeafDepth = static_cast<int>(GeometryTree::DEPTH) - 1;  // 3 for the 5-4-3 tree

// Edge length in voxels of the region a value found at tree depth `depth` stands for:
// -1 (background, no root child) and 0 (root tile) cover a whole upper internal node.
int regionDim(int depth) {
  switch (depth) {
    case -1:
    case 0: return GeometryTree::RootNodeType::ChildNodeType::DIM;
    case 1: return GeometryTree::RootNodeType::ChildNodeType::ChildNodeType::DIM;
    default: return GeometryTree::LeafNodeType::DIM;
  }
}

// Step as a fraction of the TSDF value in front of the surface. The stored TSDF is measured along
// the integrating cameras' rays, so it can exceed the true distance; stepping a little less than
// it keeps the next sample inside the negative band behind the surface instead of past it.
constexpr double kTsdfStepFraction = 0.8;
// Smallest step, in voxels: where the TSDF is unknown or tiny.
constexpr double kMinStepVoxels = 0.5;
constexpr int kRefineIterations = 2;

}  // namespace

RayMarcher::RayMarcher(const volume::LabeledVolume& volume, bool skip_empty_space)
    : sampler_(volume),
      accessor_(volume.geometryGrid().getConstAccessor()),
      voxel_size_(volume.voxelSize()),
      skip_empty_space_(skip_empty_space) {}

double RayMarcher::skipEmpty(const openvdb::Coord& ijk, const Eigen::Vector3d& index_origin,
                             const Eigen::Vector3d& index_direction, double t) {
  const int depth = accessor_.getValueDepth(ijk);
  if (depth == kLeafDepth) return t;
  const int dim = regionDim(depth);
  // Exit of the ray from the aligned cube [lo, lo + dim) of voxel indices. A sample at continuous
  // index x reads voxels floor(x) and floor(x) + 1, so the cube's far side is a safe exit.
  double t_exit = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double d = index_direction[axis];
    if (d == 0.0) continue;
    const int lo = ijk[axis] & ~(dim - 1);
    const double face = d > 0.0 ? lo + dim : lo;
    t_exit = std::min(t_exit, (face - index_origin[axis]) / d);
  }
  return std::max(t_exit, t);
}

bool RayMarcher::findSurface(const MarchRay& ray, double& t_surface) {
  const double metres_per_t = ray.direction.norm();
  const double min_step = kMinStepVoxels * voxel_size_ / metres_per_t;
  // Index space: voxel (i,j,k) is centred at world (i,j,k) * voxel_size.
  const Eigen::Vector3d index_origin = ray.origin / voxel_size_;
  const Eigen::Vector3d index_direction = ray.direction / voxel_size_;
  const double t_nudge = 1e-3 / index_direction.norm();  // a thousandth of a voxel

  bool have_positive = false;  // previous sample valid and in front of a surface
  double t_prev = 0.0;
  float f_prev = 0.0f;
  double t = ray.t_min;
  while (t < ray.t_max) {
    const Eigen::Vector3d x = index_origin + t * index_direction;
    if (skip_empty_space_) {
      const openvdb::Coord ijk(static_cast<int>(std::floor(x.x())), static_cast<int>(std::floor(x.y())),
                               static_cast<int>(std::floor(x.z())));
      const double t_next = skipEmpty(ijk, index_origin, index_direction, t);
      if (t_next > t) {
        t = t_next + t_nudge;
        have_positive = false;
        continue;
      }
    }
    float f;
    if (!sampler_.tsdf(Eigen::Vector3f((ray.origin + t * ray.direction).cast<float>()), f)) {
      have_positive = false;
      t += min_step;
      continue;
    }
    if (f <= 0.0f && have_positive) {
      t_surface = refineCrossing(ray, t_prev, f_prev, t, f);
      return true;
    }
    have_positive = f > 0.0f;
    t_prev = t;
    f_prev = f;
    t += f > 0.0f ? std::max(min_step, kTsdfStepFraction * f / metres_per_t) : min_step;
  }
  return false;
}

double RayMarcher::refineCrossing(const MarchRay& ray, double t_pos, float f_pos, double t_neg, float f_neg) {
  auto secant = [&] { return t_pos + (t_neg - t_pos) * f_pos / static_cast<double>(f_pos - f_neg); };
  for (int i = 0; i < kRefineIterations; ++i) {
    const double t_mid = secant();
    float f_mid;
    if (!sampler_.tsdf(Eigen::Vector3f((ray.origin + t_mid * ray.direction).cast<float>()), f_mid)) break;
    if (f_mid > 0.0f) {
      t_pos = t_mid;
      f_pos = f_mid;
    } else {
      t_neg = t_mid;
      f_neg = f_mid;
    }
    if (f_pos - f_neg <= 0.0f) break;
  }
  return f_pos - f_neg > 0.0f ? secant() : t_neg;
}

}  // namespace semfuse::render::detail
