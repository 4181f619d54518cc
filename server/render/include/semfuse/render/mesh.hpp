#pragma once
// Labeled triangle mesh of a volume's surface: one vertex per piece of the TSDF's zero level in
// each voxel cell it crosses, one quad (two triangles) per crossed voxel edge, restricted to
// observed cells, so that no surface is invented against never-seen space. Each vertex carries
// the label, score and colour of its nearest voxel and a normal from the TSDF gradient.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "semfuse/core/result.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render {

struct LabeledMesh {
  std::vector<Eigen::Vector3f> vertices;           // world, metres
  std::vector<Eigen::Vector3f> normals;            // unit, towards free space; one per vertex
  std::vector<LabelId> labels;                     // one per vertex, 0 = unlabeled
  std::vector<float> scores;                       // one per vertex
  std::vector<volume::Rgb8> colors;                // one per vertex; empty when the volume has no colour
  std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from free space
};

struct WorldBounds {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};

// Both place one vertex per piece of surface in each crossed cell and join the cells around each
// crossed edge, so their meshes agree up to the cells and quads at the rim of the observed region
// that VolumeToMesh's eroded mask drops.
enum class MeshMethod {
  // Default, ~4x less CPU: surface nets over the leaves the zero level crosses, parallel over
  // leaves, with the vertex attributes taken from the cell's own corners (mesh_surface_nets.cpp).
  kSurfaceNets,
  // openvdb::tools::VolumeToMesh on a FloatGrid copy of the TSDF with an eroded observation mask:
  // the reference surface nets are tested against.
  kOpenVdbVolumeToMesh,
};

struct MeshOptions {
  std::optional<WorldBounds> bounds;  // mesh only the cells inside this box
  MeshMethod method = MeshMethod::kSurfaceNets;
};

// Fails on a bounding box that is empty or not finite.
Result<LabeledMesh> extractMesh(const volume::LabeledVolume& volume, const MeshOptions& options = {});

}  // namespace semfuse::render
