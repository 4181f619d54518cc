#pragma once
// Test fixture helper: a volume fused from exact renderings of an analytic scene, so raycasts and
// meshes can be compared with the scene's own depth and distance field.
#include <vector>

#include <gtest/gtest.h>

#include "semfuse/synthetic/labeled_scene.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::testing {

inline const PinholeIntrinsics kSmallCamera{320, 240, 262.5, 262.5, 159.5, 119.5};

// The volume the fused test scenes use: 1 cm voxels, 4 cm truncation (VolumeParams' defaults).
inline constexpr double kVoxel = 0.01;
inline volume::VolumeParams fusedVolumeParams() {
  volume::VolumeParams p;
  p.voxel_size = kVoxel;
  p.truncation = 0.04;
  return p;
}

// Poses on an arc around target at the given distance and height, looking at it.
inline std::vector<Pose> arcAround(const Eigen::Vector3d& target, double distance, double height, int count,
                                   double arc_rad = 1.2) {
  std::vector<Pose> poses;
  for (int i = 0; i < count; ++i) {
    const double a = -0.5 * arc_rad + arc_rad * i / std::max(1, count - 1);
    const Eigen::Vector3d eye = target + Eigen::Vector3d(-distance * std::cos(a), distance * std::sin(a), height);
    poses.push_back(synthetic::lookAt(eye, target));
  }
  return poses;
}

// Integrates exact depth, colour and (with_labels) ground-truth labels of every pose.
inline void fuse(volume::LabeledVolume& volume, const synthetic::LabeledScene& scene, const std::vector<Pose>& poses,
                 const PinholeIntrinsics& camera = kSmallCamera, bool with_labels = true) {
  for (const Pose& pose : poses) {
    const auto view = synthetic::renderView(scene, camera, pose);
    ASSERT_TRUE(view.ok()) << view.error();
    const auto& v = view.value();
    const auto stats = with_labels ? volume::integrate(volume, v.depth, v.color, v.labels, cv::Mat(), camera, pose)
                                   : volume::integrate(volume, v.depth, v.color, camera, pose);
    ASSERT_TRUE(stats.ok()) << stats.error();
  }
}

}  // namespace semfuse::render::testing
