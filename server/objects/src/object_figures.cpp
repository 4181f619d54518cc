#include "semfuse/objects/object_figures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

namespace semfuse::objects {
namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; counter-clockwise, no repeated first point.
std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Two unit vectors that make a right-handed frame with up.
void planeAxes(const Eigen::Vector3d& up, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  const Eigen::Vector3d seed = std::abs(up.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  e1 = (seed - seed.dot(up) * up).normalized();
  e2 = up.cross(e1);
}

OrientedBox boxAlong(const Eigen::Matrix3d& axes, const std::vector<Eigen::Vector3d>& points, double margin) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : points) {
    const Eigen::Vector3d local = axes.transpose() * p;
    lo = lo.cwiseMin(local);
    hi = hi.cwiseMax(local);
  }
  OrientedBox box;
  box.axes = axes;
  box.center = axes * (0.5 * (lo + hi));
  box.half_extents = 0.5 * (hi - lo) + Eigen::Vector3d::Constant(margin);
  return box;
}

OrientedBox uprightBox(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up, double voxel) {
  Eigen::Vector3d e1, e2;
  planeAxes(up, e1, e2);
  // The footprint's hull only needs, per column of the plane, the lowest and highest point.
  std::unordered_map<int64_t, std::pair<double, double>> columns;
  for (const auto& p : points) {
    const double u = p.dot(e1), v = p.dot(e2);
    auto [it, added] = columns.try_emplace(static_cast<int64_t>(std::floor(u / voxel)), v, v);
    if (!added) it->second = {std::min(it->second.first, v), std::max(it->second.second, v)};
  }
  std::vector<Eigen::Vector2d> footprint;
  for (const auto& [column, span] : columns) {
    const double u = (column + 0.5) * voxel;
    footprint.emplace_back(u, span.first);
    footprint.emplace_back(u, span.second);
  }
  const Rectangle2d rect = minimumAreaRectangle(std::move(footprint));
  const Eigen::Vector3d a1 = (rect.axis.x() * e1 + rect.axis.y() * e2).normalized();
  Eigen::Matrix3d axes;
  axes.col(0) = a1;
  axes.col(1) = up.cross(a1);
  axes.col(2) = up;
  return boxAlong(axes, points, 0.5 * voxel);
}

OrientedBox principalBox(const std::vector<Eigen::Vector3d>& points, double voxel) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : points) covariance += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d axes = solver.eigenvectors().rowwise().reverse();  // largest first
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  return boxAlong(axes, points, 0.5 * voxel);
}

}  // namespace

Rectangle2d minimumAreaRectangle(std::vector<Eigen::Vector2d> points) {
  Rectangle2d best;
  if (points.empty()) return best;
  const std::vector<Eigen::Vector2d> hull = convexHull(std::move(points));
  if (hull.size() < 3) {
    const Eigen::Vector2d d = hull.size() == 2 ? Eigen::Vector2d(hull[1] - hull[0]) : Eigen::Vector2d::Zero();
    best.axis = d.norm() > 0 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d::UnitX();
    best.center = hull.size() == 2 ? Eigen::Vector2d(0.5 * (hull[0] + hull[1])) : hull[0];
    best.half_extents = Eigen::Vector2d(0.5 * d.norm(), 0.0);
    return best;
  }
  double best_area = std::numeric_limits<double>::infinity();
  // The smallest rectangle has a side on a hull edge: try each edge's direction.
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d edge = hull[(i + 1) % hull.size()] - hull[i];
    if (edge.norm() == 0) continue;
    const Eigen::Vector2d a = edge.normalized(), b(-a.y(), a.x());
    double lo_a = std::numeric_limits<double>::infinity(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
    for (const auto& p : hull) {
      lo_a = std::min(lo_a, p.dot(a));
      hi_a = std::max(hi_a, p.dot(a));
      lo_b = std::min(lo_b, p.dot(b));
      hi_b = std::max(hi_b, p.dot(b));
    }
    const double area = (hi_a - lo_a) * (hi_b - lo_b);
    if (area < best_area) {
      best_area = area;
      best.axis = a;
      best.center = a * 0.5 * (lo_a + hi_a) + b * 0.5 * (lo_b + hi_b);
      best.half_extents = Eigen::Vector2d(0.5 * (hi_a - lo_a), 0.5 * (hi_b - lo_b));
    }
  }
  return best;
}

std::vector<ObjectFigures> measureGroups(const SurfaceVoxels& surface, const Grouping& grouping,
                                         const Eigen::Vector3d& up) {
  const std::size_t count = grouping.groups.size();
  std::vector<std::vector<uint32_t>> members(count);
  for (std::size_t i = 0; i < surface.size(); ++i) members[grouping.group_of[i]].push_back(static_cast<uint32_t>(i));
  const double voxel = surface.voxelSize();
  const bool upright = up.norm() > 0.5;
  const Eigen::Vector3d unit_up = upright ? Eigen::Vector3d(up.normalized()) : Eigen::Vector3d::Zero();
  std::vector<ObjectFigures> figures(count);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t g) {
    ObjectFigures& f = figures[g];
    const std::vector<uint32_t>& voxels = members[g];
    if (voxels.empty()) return;
    std::vector<Eigen::Vector3d> points;
    points.reserve(voxels.size());
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double score = 0.0;
    for (uint32_t i : voxels) {
      const Eigen::Vector3d p = surface.position(i);
      points.push_back(p);
      sum += p;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      f.area_m2 += surface[i].area_m2;
      score += surface[i].score;
      const openvdb::Coord leaf = surface[i].ijk & ~7;
      if (f.leaves.empty() || f.leaves.back() != leaf) f.leaves.push_back(leaf);
    }
    std::sort(f.leaves.begin(), f.leaves.end());
    f.leaves.erase(std::unique(f.leaves.begin(), f.leaves.end()), f.leaves.end());
    f.voxel_count = voxels.size();
    f.centroid = sum / static_cast<double>(voxels.size());
    f.bbox_min = lo - Eigen::Vector3d::Constant(0.5 * voxel);
    f.bbox_max = hi + Eigen::Vector3d::Constant(0.5 * voxel);
    f.mean_confidence = static_cast<float>(score / static_cast<double>(voxels.size()));
    f.box = upright ? uprightBox(points, unit_up, voxel) : principalBox(points, voxel);
  });
  return figures;
}

}  // namespace semfuse::objects
