#pragma once
// Smooth, deterministic camera paths through the synthetic room.
#include <Eigen/Core>

#include "semfuse/core/types.hpp"

namespace semfuse::synthetic {

// Camera-to-world pose of a camera at eye looking at target, with world +z as "up" in the image
// (OpenCV camera axes: x right, y down, z forward). eye and target must differ and the view
// direction must not be vertical.
Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
            const Eigen::Vector3d& world_up = Eigen::Vector3d::UnitZ());

// An orbit around the room's centre whose height and gaze wander on Lissajous curves, so that
// consecutive frames move a few centimetres and degrees (trackable) while the whole sequence sees
// every side of every object. The path is periodic with frame_count frames.
struct OrbitTrajectory {
  int frame_count = 300;
  double revolutions = 1.0;
  Eigen::Vector2d center{0.0, 0.0};  // orbit centre in the floor plane
  double radius = 1.6;
  double height = 1.4;  // mean eye height
  double height_amplitude = 0.2;
  Eigen::Vector3d target{0.0, 0.0, 0.6};
  double target_amplitude = 0.35;  // how far the gaze point wanders around target
  double phase_rad = 0.0;          // start angle on the orbit

  Pose pose(double frame) const;  // fractional frames give in-between poses
};

}  // namespace semfuse::synthetic
