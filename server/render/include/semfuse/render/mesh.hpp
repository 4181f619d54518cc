#pragma once
// Labeled triangle mesh of a volume's surface: OpenVDB marching cubes (tools::VolumeToMesh) on
// the TSDF, restricted to cells whose 8 corners were all observed, so that no surface is invented
// against never-seen space. Each vertex carries the label, score and colour of its nearest voxel
// and a normal from the TSDF gradient.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "semfuse/core/result.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render {

struct LabeledMesh {
  std::vector<Eigen::Vector3f> vertices;      // world, metres
  std::vector<Eigen::Vector3f> normals;       // unit, towards free space; one per vertex
  std::vector<LabelId> labels;                // one per vertex, 0 = unlabeled
  std::vector<float> scores;                  // one per vertex
  std::vector<volume::Rgb8> colors;           // one per vertex; empty when the volume has no colour
  std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from free space
};

struct WorldBounds {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};

struct MeshOptions {
  std::optional<WorldBounds> bounds;  // mesh only the cells inside this box
};

// Fails on a bounding box that is empty or not finite.
Result<LabeledMesh> extractMesh(const volume::LabeledVolume& volume, const MeshOptions& options = {});

}  // namespace semfuse::render
