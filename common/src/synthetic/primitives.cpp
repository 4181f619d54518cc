#include "semfuse/synthetic/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace semfuse::synthetic {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Slab test in the box's own frame: the entry is the largest of the per-axis near planes.
std::optional<RayHit> intersectBox(const OrientedBox& box, const Ray& ray, double t_min) {
  const Eigen::Matrix3d box_from_world = box.world_from_box.transpose();
  const Eigen::Vector3d o = box_from_world * (ray.origin - box.center);
  const Eigen::Vector3d d = box_from_world * ray.direction;
  double t_near = -kInf, t_far = kInf;
  int near_axis = -1;
  for (int axis = 0; axis < 3; ++axis) {
    const double h = box.half_extents[axis];
    if (std::abs(d[axis]) < 1e-15) {
      if (std::abs(o[axis]) > h) return std::nullopt;  // parallel to and outside this slab
      continue;
    }
    double t0 = (-h - o[axis]) / d[axis];
    double t1 = (h - o[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) {
      t_near = t0;
      near_axis = axis;
    }
    t_far = std::min(t_far, t1);
  }
  if (near_axis < 0 || t_near > t_far || t_near <= t_min) return std::nullopt;
  Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
  local_normal[near_axis] = d[near_axis] > 0 ? -1.0 : 1.0;
  return RayHit{t_near, box.world_from_box * local_normal};
}

std::optional<RayHit> intersectSphere(const Sphere& s, const Ray& ray, double t_min) {
  const Eigen::Vector3d oc = ray.origin - s.center;
  const double a = ray.direction.squaredNorm();
  const double half_b = oc.dot(ray.direction);
  const double c = oc.squaredNorm() - s.radius * s.radius;
  if (c < 0.0) return std::nullopt;  // origin inside
  const double disc = half_b * half_b - a * c;
  if (disc < 0.0) return std::nullopt;
  const double t = (-half_b - std::sqrt(disc)) / a;
  if (t <= t_min) return std::nullopt;
  return RayHit{t, (ray.origin + t * ray.direction - s.center) / s.radius};
}

std::optional<RayHit> intersectCylinder(const UprightCylinder& cyl, const Ray& ray, double t_min) {
  const Eigen::Vector2d o(ray.origin.x() - cyl.center.x(), ray.origin.y() - cyl.center.y());
  const Eigen::Vector2d d(ray.direction.x(), ray.direction.y());
  const double r2 = cyl.radius * cyl.radius;
  const bool inside_radially = o.squaredNorm() < r2;
  const double oz = ray.origin.z(), dz = ray.direction.z();
  if (inside_radially && oz > cyl.z_min && oz < cyl.z_max) return std::nullopt;  // origin inside

  std::optional<RayHit> best;
  auto consider = [&](double t, const Eigen::Vector3d& n) {
    if (t > t_min && (!best || t < best->t)) best = RayHit{t, n};
  };
  // Mantle: entry root of |o + t d|^2 = r^2, valid where the hit lies between the caps.
  const double a = d.squaredNorm();
  if (a > 1e-15 && !inside_radially) {
    const double half_b = o.dot(d);
    const double disc = half_b * half_b - a * (o.squaredNorm() - r2);
    if (disc >= 0.0) {
      const double t = (-half_b - std::sqrt(disc)) / a;
      const double z = oz + t * dz;
      if (z >= cyl.z_min && z <= cyl.z_max) {
        const Eigen::Vector2d radial = (o + t * d) / cyl.radius;
        consider(t, Eigen::Vector3d(radial.x(), radial.y(), 0.0));
      }
    }
  }
  // Caps: the ray can only enter through the cap facing its origin.
  if (std::abs(dz) > 1e-15) {
    const bool from_above = dz < 0.0;
    const double z_cap = from_above ? cyl.z_max : cyl.z_min;
    const double t = (z_cap - oz) / dz;
    if ((o + t * d).squaredNorm() <= r2) consider(t, Eigen::Vector3d(0, 0, from_above ? 1.0 : -1.0));
  }
  return best;
}

double boxDistance(const OrientedBox& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = box.world_from_box.transpose() * (p - box.center);
  const Eigen::Vector3d q = local.cwiseAbs() - box.half_extents;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

double cylinderDistance(const UprightCylinder& cyl, const Eigen::Vector3d& p) {
  const double radial = Eigen::Vector2d(p.x() - cyl.center.x(), p.y() - cyl.center.y()).norm();
  const double half_height = 0.5 * (cyl.z_max - cyl.z_min);
  const Eigen::Vector2d q(radial - cyl.radius, std::abs(p.z() - 0.5 * (cyl.z_min + cyl.z_max)) - half_height);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace

std::optional<RayHit> intersect(const Shape& shape, const Ray& ray, double t_min) {
  return std::visit(Overloaded{
                        [&](const OrientedBox& b) { return intersectBox(b, ray, t_min); },
                        [&](const Sphere& s) { return intersectSphere(s, ray, t_min); },
                        [&](const UprightCylinder& c) { return intersectCylinder(c, ray, t_min); },
                    },
                    shape);
}

double signedDistance(const Shape& shape, const Eigen::Vector3d& p) {
  return std::visit(Overloaded{
                        [&](const OrientedBox& b) { return boxDistance(b, p); },
                        [&](const Sphere& s) { return (p - s.center).norm() - s.radius; },
                        [&](const UprightCylinder& c) { return cylinderDistance(c, p); },
                    },
                    shape);
}

Aabb bounds(const Shape& shape) {
  return std::visit(Overloaded{
                        [](const OrientedBox& b) {
                          // Extent along each world axis = sum of |box axis component| * half extent.
                          const Eigen::Vector3d e = b.world_from_box.cwiseAbs() * b.half_extents;
                          return Aabb{b.center - e, b.center + e};
                        },
                        [](const Sphere& s) {
                          return Aabb{(s.center.array() - s.radius).matrix(), (s.center.array() + s.radius).matrix()};
                        },
                        [](const UprightCylinder& c) {
                          return Aabb{Eigen::Vector3d(c.center.x() - c.radius, c.center.y() - c.radius, c.z_min),
                                      Eigen::Vector3d(c.center.x() + c.radius, c.center.y() + c.radius, c.z_max)};
                        },
                    },
                    shape);
}

}  // namespace semfuse::synthetic
