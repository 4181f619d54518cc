#pragma once
// Shared set-up of the tracking tests: the synthetic room, a camera that sees a good part of it,
// and rigid offsets of the size the tracker must recover (rotation <= 10 deg, translation <= 10 cm).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "semfuse/core/types.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"
#include "semfuse/tracking/se3.hpp"
#include "semfuse/volume/volume_params.hpp"

namespace semfuse::tracking::testing {

// A geometry-only map (no colour) for tracking against: the truncation band sets the basin of
// convergence, the voxel size the fixture's speed.
inline volume::VolumeParams geometryMapParams(double voxel_size, double truncation) {
  volume::VolumeParams params;
  params.voxel_size = voxel_size;
  params.truncation = truncation;
  params.integrate_color = false;
  return params;
}

inline PinholeIntrinsics kinectIntrinsics() { return {640, 480, 585.0, 585.0, 320.0, 240.0}; }

// Looks across the room at the table and the far corner: floor, two walls and furniture in view.
inline Pose referencePose() {
  return synthetic::lookAt(Eigen::Vector3d(1.3, -1.1, 1.5), Eigen::Vector3d(-0.3, 0.4, 0.7));
}

// Inside of the default synthetic room (5 x 4 x 2.6 m, floor at z = 0): what a camera in it sees.
inline Eigen::AlignedBox3d roomInterior() {
  // 5 cm margin: surface points must not fall outside through rounding.
  return {Eigen::Vector3d(-2.55, -2.05, -0.05), Eigen::Vector3d(2.55, 2.05, 2.65)};
}

// A short smooth path from referencePose(): 2 cm and 0.5 degrees per step, turning towards the
// far corner.
inline Pose pathPose(int i) {
  Pose step = Pose::Identity();
  step.linear() = Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  step.translation() = Eigen::Vector3d(0.02, 0.0, 0.0);
  Pose pose = referencePose();
  for (int k = 0; k < i; ++k) pose = pose * step;
  return pose;
}

struct RigidOffset {
  Eigen::Vector3d axis;
  double angle_deg;
  Eigen::Vector3d translation_m;
};

// Offsets applied on the left of the true pose (world frame) to make the starting guess.
inline std::vector<RigidOffset> offsetsToRecover() {
  return {
      {Eigen::Vector3d::UnitZ(), 0.0, {0.10, 0.0, 0.0}},
      {Eigen::Vector3d::UnitZ(), 0.0, {0.0, -0.06, 0.08}},
      {Eigen::Vector3d::UnitZ(), 10.0, {0.0, 0.0, 0.0}},
      {Eigen::Vector3d::UnitX(), -10.0, {0.0, 0.0, 0.0}},
      {Eigen::Vector3d(1.0, -2.0, 0.5), 7.0, {0.05, 0.05, -0.05}},
      {Eigen::Vector3d(-0.3, 1.0, 1.0), 10.0, {-0.06, 0.04, 0.07}},
  };
}

inline Pose applyOffset(const RigidOffset& offset, const Pose& truth) {
  Pose delta = Pose::Identity();
  // Rotate about the camera centre so that the translation part is exactly what is stated.
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(offset.angle_deg * M_PI / 180.0, offset.axis.normalized()).toRotationMatrix();
  delta.linear() = r;
  delta.translation() = truth.translation() - r * truth.translation() + offset.translation_m;
  return delta * truth;
}

inline double translationError(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
inline double rotationErrorDeg(const Pose& a, const Pose& b) {
  return rotationAngle(a.linear().transpose() * b.linear()) * 180.0 / M_PI;
}

inline synthetic::RenderedView renderOrDie(const synthetic::LabeledScene& scene, const Pose& pose) {
  Result<synthetic::RenderedView> view = synthetic::renderView(scene, kinectIntrinsics(), pose);
  EXPECT_TRUE(view.ok()) << (view.ok() ? "" : view.error());
  return std::move(view).value();
}

}  // namespace semfuse::tracking::testing
