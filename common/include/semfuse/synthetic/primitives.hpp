#pragma once
// Analytic solids of the synthetic scene: exact ray intersection and exact signed distance.
// Everything is in world coordinates, metres. A signed distance is positive outside the solid.
#include <optional>
#include <variant>

#include <Eigen/Core>

namespace semfuse::synthetic {

// A ray o + t * d. d need not be unit length: with d = R * (x, y, 1) (a pixel's ray in camera
// coordinates rotated to world) t is the camera-frame depth of the hit, which is what a depth
// image stores.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
};

// Entry point of a ray into a solid: ray parameter and the outward unit normal there.
struct RayHit {
  double t = 0.0;
  Eigen::Vector3d normal;
};

// Box with centre, half extents along its own axes, and orientation (columns = box axes in world).
struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Constant(0.5);
  Eigen::Matrix3d world_from_box = Eigen::Matrix3d::Identity();
};

struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.5;
};

// Closed cylinder whose axis is the world z axis through (center.x, center.y), spanning
// z_min..z_max (furniture legs, posts).
struct UprightCylinder {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.1;
  double z_min = 0.0;
  double z_max = 1.0;
};

using Shape = std::variant<OrientedBox, Sphere, UprightCylinder>;

// First entry of the ray into the solid with t > t_min. A ray starting inside the solid never
// enters it and returns nothing: the scene is only ever seen from free space.
std::optional<RayHit> intersect(const Shape& shape, const Ray& ray, double t_min = 0.0);

// Exact Euclidean signed distance from p to the solid's surface (negative inside).
double signedDistance(const Shape& shape, const Eigen::Vector3d& p);

// Axis-aligned bounds of the solid, for culling.
struct Aabb {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};
Aabb bounds(const Shape& shape);

}  // namespace semfuse::synthetic
