#pragma once
// The synthetic room fused at 5 cm from exact depth and ground-truth labels along two orbits (a
// high one that looks down on the furniture and a low one that sees under the table) and two
// rings of views out towards the walls, and views down from the corners, with its
// observed free space, and the distance field kept up to date frame by frame as a server does;
// beside it a field of twice the map's voxel (10 cm), which samples the TSDF at every other voxel.
// Built once per test program (it takes a few seconds).
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "semfuse/esdf/esdf_map.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"
#include "semfuse/volume/free_space.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::esdf::testing {

inline constexpr double kVoxel = 0.05;
inline constexpr double kMaxDistance = 1.0;
inline constexpr int kCoarseStride = 2;
inline constexpr double kCoarseVoxel = kCoarseStride * kVoxel;
inline const PinholeIntrinsics kCamera{320, 240, 262.5, 262.5, 159.5, 119.5};

struct FusedRoom {
  synthetic::LabeledScene scene = synthetic::makeRoom();
  std::unique_ptr<volume::LabeledVolume> volume;
  std::unique_ptr<EsdfMap> esdf;
  std::unique_ptr<EsdfMap> coarse;  // kCoarseVoxel
  std::vector<Pose> poses;
};

inline std::vector<Pose> roomPoses() {
  std::vector<Pose> poses;
  synthetic::OrbitTrajectory high;
  high.frame_count = 48;
  synthetic::OrbitTrajectory low = high;
  low.frame_count = 32;
  low.height = 0.3;
  low.height_amplitude = 0.05;
  low.radius = 1.3;  // clear of the furniture: the chairs reach 1.16 m from the centre, the big sphere 1.43 m
  low.target = {0.0, 0.0, 0.45};
  low.target_amplitude = 0.2;
  low.phase_rad = 0.3;
  for (int i = 0; i < high.frame_count; ++i) poses.push_back(high.pose(i));
  for (int i = 0; i < low.frame_count; ++i) poses.push_back(low.pose(i));
  // From above the table looking out at the walls, the boxes and the cabinet, which the orbits
  // see only from across the room.
  constexpr int kOutward = 24;
  for (int i = 0; i < kOutward; ++i) {
    const double a = 2.0 * M_PI * i / kOutward;
    const Eigen::Vector3d eye(0.2 + 0.3 * std::cos(a), 0.1 + 0.3 * std::sin(a), 1.3);
    const Eigen::Vector3d target(0.2 + 2.0 * std::cos(a), 0.1 + 1.6 * std::sin(a), 0.3);
    poses.push_back(synthetic::lookAt(eye, target));
  }
  // From 1.5 m out, high, looking down past the furniture into the strip along the walls.
  for (int i = 0; i < kOutward; ++i) {
    const double a = 2.0 * M_PI * (i + 0.5) / kOutward;
    const Eigen::Vector3d eye(1.5 * std::cos(a), 1.2 * std::sin(a), 1.7);
    const Eigen::Vector3d target(2.3 * std::cos(a), 1.85 * std::sin(a), 0.0);
    poses.push_back(synthetic::lookAt(eye, target));
  }
  // From high in each corner, down behind the boxes and the big sphere that stand near them.
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d eye(sx * 2.25, sy * 1.75, 1.9);
        const Eigen::Vector3d target(sx * (1.2 + 0.25 * (k % 2)), sy * (0.9 + 0.25 * (k / 2)), 0.1);
        poses.push_back(synthetic::lookAt(eye, target));
      }
  return poses;
}

inline volume::VolumeParams roomVolumeParams() {
  volume::VolumeParams params;
  params.voxel_size = kVoxel;
  params.truncation = 2 * kVoxel;
  params.integrate_color = false;
  params.label_rule = volume::LabelRule::kEvidence;
  params.max_depth = 8.0f;
  return params;
}

inline EsdfParams roomEsdfParams() {
  EsdfParams params;
  params.max_distance = kMaxDistance;
  return params;
}

inline EsdfParams coarseEsdfParams() {
  EsdfParams params = roomEsdfParams();
  params.voxel_size = kCoarseVoxel;
  return params;
}

// Integrates one view (depth + labels + free space) and updates the field from the changes.
inline void fuseView(FusedRoom& room, const Pose& pose) {
  const auto view = synthetic::renderView(room.scene, kCamera, pose);
  ASSERT_TRUE(view.ok()) << view.error();
  const auto& v = view.value();
  ASSERT_TRUE(volume::integrate(*room.volume, v.depth, cv::Mat(), v.labels, cv::Mat(), kCamera, pose).ok());
  ASSERT_TRUE(volume::observeFreeSpace(*room.volume, v.depth, kCamera, pose).ok());
  room.esdf->apply(copyChanges(*room.volume, room.esdf->revision()));
  room.coarse->apply(copyChanges(*room.volume, room.coarse->revision(), kCoarseStride));
}

inline const FusedRoom& fusedRoom() {
  static const std::unique_ptr<FusedRoom> room = [] {
    auto r = std::make_unique<FusedRoom>();
    r->volume = std::make_unique<volume::LabeledVolume>(roomVolumeParams());
    r->esdf = std::make_unique<EsdfMap>(kVoxel, roomEsdfParams());
    r->coarse = std::make_unique<EsdfMap>(kCoarseVoxel, coarseEsdfParams());
    r->poses = roomPoses();
    for (const Pose& pose : r->poses) fuseView(*r, pose);
    return r;
  }();
  return *room;
}

inline Eigen::Vector3d centreOf(const openvdb::Coord& ijk) {
  return Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()) * kVoxel;
}

}  // namespace semfuse::esdf::testing
