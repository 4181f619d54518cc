#pragma once
// Depth images of analytic shapes (plane, sphere) rendered exactly for a pinhole camera, so that
// tests know the true surface the volume must reproduce.
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "semfuse/core/types.hpp"

namespace semfuse::volume::testing {

inline PinholeIntrinsics smallCamera() { return {160, 120, 150.0, 150.0, 79.5, 59.5}; }

// Camera-to-world pose at `eye` looking at `target` (camera z forward, x right, y down).
inline Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                   const Eigen::Vector3d& up = Eigen::Vector3d(0, -1, 0)) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = (-up).cross(z).normalized();  // y down = -up
  const Eigen::Vector3d y = z.cross(x);
  Pose pose = Pose::Identity();
  pose.linear() << x, y, z;
  pose.translation() = eye;
  return pose;
}

// Depth (metres along the camera z axis) of the first hit of each pixel's ray; `hit(origin, dir)`
// returns the ray parameter t (world units, dir with camera-z component 1) or a negative value.
template <typename Hit>
cv::Mat renderDepth(const PinholeIntrinsics& k, const Pose& camera_to_world, Hit hit) {
  cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(0));
  const Eigen::Vector3d origin = camera_to_world.translation();
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const double t = hit(origin, Eigen::Vector3d(camera_to_world.linear() * ray_cam));
      if (t > 0) depth.at<float>(v, u) = static_cast<float>(t);  // z of ray_cam is 1: t is depth
    }
  return depth;
}

// Plane n . x = offset (n unit length).
inline cv::Mat renderPlane(const PinholeIntrinsics& k, const Pose& pose, const Eigen::Vector3d& n, double offset) {
  return renderDepth(k, pose, [&](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    const double denom = n.dot(d);
    return std::abs(denom) < 1e-12 ? -1.0 : (offset - n.dot(o)) / denom;
  });
}

inline cv::Mat renderSphere(const PinholeIntrinsics& k, const Pose& pose, const Eigen::Vector3d& centre,
                            double radius) {
  return renderDepth(k, pose, [&](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    const Eigen::Vector3d oc = o - centre;
    const double a = d.squaredNorm(), b = 2 * oc.dot(d), c = oc.squaredNorm() - radius * radius;
    const double disc = b * b - 4 * a * c;
    return disc < 0 ? -1.0 : (-b - std::sqrt(disc)) / (2 * a);
  });
}

}  // namespace semfuse::volume::testing
