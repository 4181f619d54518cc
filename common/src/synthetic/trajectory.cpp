#include "semfuse/synthetic/trajectory.hpp"

#include <cmath>

namespace semfuse::synthetic {

Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& world_up) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(world_up).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Pose pose = Pose::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = down;
  pose.linear().col(2) = forward;
  pose.translation() = eye;
  return pose;
}

Pose OrbitTrajectory::pose(double frame) const {
  const double s = frame_count > 0 ? frame / frame_count : 0.0;  // one period = [0, 1)
  const double angle = phase_rad + 2.0 * M_PI * revolutions * s;
  // Integer frequencies keep the path closed over one period.
  const double height_wave = std::sin(2.0 * M_PI * 2.0 * s);
  const Eigen::Vector3d eye(center.x() + radius * std::cos(angle), center.y() + radius * std::sin(angle),
                            height + height_amplitude * height_wave);
  const Eigen::Vector3d gaze =
      target + target_amplitude * Eigen::Vector3d(std::sin(2.0 * M_PI * 3.0 * s), std::cos(2.0 * M_PI * 2.0 * s),
                                                  0.5 * std::sin(2.0 * M_PI * s));
  return lookAt(eye, gaze);
}

}  // namespace semfuse::synthetic
