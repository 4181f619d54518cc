#pragma once
// Internal: the per-leaf voxel update of projective integration, shared by the scalar kernel
// (below, portable) and the AVX2 + F16C kernel (leaf_update_avx2.cpp). Both must give the same
// bits for every voxel: same operations in the same order, no fused multiply-add, IEEE
// round-to-nearest-even half conversions (tests/volume/integrate_kernels_test.cpp compares them).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "frame_view.hpp"
#include "semfuse/volume/label_rules.hpp"
#include "semfuse/volume/labeled_volume.hpp"
#include "semfuse/volume/voxel.hpp"

namespace semfuse::volume::detail {

using GeometryLeaf = GeometryGrid::TreeType::LeafNodeType;
using ColorLeaf = ColorGrid::TreeType::LeafNodeType;
using LabelSidecarLeaf = LabelSidecarGrid::TreeType::LeafNodeType;
inline constexpr int kLeafDim = static_cast<int>(GeometryLeaf::DIM);

// One leaf to update: its geometry and (when the volume has them) its colour and label-sidecar twins.
struct LeafPair {
  GeometryLeaf* geometry;
  ColorLeaf* color;
  LabelSidecarLeaf* label_sidecar = nullptr;
};

// Labels that never change a voxel: 0 and the background set, one bit per label id in 32-bit
// words, so that the per-voxel test is one load (and the AVX2 kernel's, one gather for 8 voxels).
class IgnoredLabels {
 public:
  explicit IgnoredLabels(const VolumeParams& params) {
    set(kUnlabeled);
    for (LabelId id : params.background_labels) set(id);
  }
  bool operator[](LabelId id) const { return (words_[id >> 5] >> (id & 31u)) & 1u; }
  const uint32_t* words() const { return words_.data(); }
  bool onlyUnlabeled() const { return only_unlabeled_; }  // no background labels: label == 0 is the test

 private:
  void set(LabelId id) {
    words_[id >> 5] |= 1u << (id & 31u);
    only_unlabeled_ = only_unlabeled_ && id == kUnlabeled;
  }
  std::array<uint32_t, 65536 / 32> words_{};
  bool only_unlabeled_ = true;
};

inline std::unique_ptr<IgnoredLabels> ignoredLabels(const VolumeParams& params) {
  return std::make_unique<IgnoredLabels>(params);
}

struct KernelConfig {
  float voxel_size;
  float truncation;
  // Where behind the surface an observation's weight starts to fall (metres) and how fast, per
  // metre (observationWeight).
  float dropoff_start;
  float dropoff_per_metre;
  float max_weight;
  float max_score;
  const IgnoredLabels* ignored;
  LabelRuleConfig label_rule;
};

// The weight of one observation of a voxel `sdf` metres in front of (positive) or behind
// (negative) the surface a depth pixel saw: 1 in front and down to VolumeParams::weight_dropoff
// of the truncation behind, then falling linearly to kMinObservationWeight at the truncation (the
// linear weight of Bylow et al. 2013; volume_params.hpp says why). The floor keeps a voxel seen
// only from behind observed (its weight above zero).
inline constexpr float kMinObservationWeight = 1.0f / 16.0f;
inline float observationWeight(float sdf, const KernelConfig& config) {
  return std::min(1.0f,
                  std::max(kMinObservationWeight, 1.0f + (sdf + config.dropoff_start) * config.dropoff_per_metre));
}

struct KernelCounts {
  std::size_t updated = 0;
  std::size_t labeled = 0;
};

// A leaf's voxel grid in camera coordinates: voxel (x, y, z) of the leaf is at
// corner + step_x * x + step_y * y + step_z * z. Both kernels start from these same floats.
struct LeafInCamera {
  Eigen::Vector3f corner, step_x, step_y, step_z;
};

inline LeafInCamera leafInCamera(const GeometryLeaf& leaf, const FrameView& frame, float voxel_size) {
  const openvdb::Coord origin = leaf.origin();
  const Eigen::Matrix3f& rotation = frame.world_to_camera_rotation;
  return {
      rotation * (Eigen::Vector3f(origin.x(), origin.y(), origin.z()) * voxel_size) + frame.world_to_camera_translation,
      rotation.col(0) * voxel_size, rotation.col(1) * voxel_size, rotation.col(2) * voxel_size};
}

// Camera coordinates of the first voxel of column (x, y) of a leaf.
inline Eigen::Vector3f columnStart(const LeafInCamera& leaf, int x, int y) {
  return leaf.corner + leaf.step_x * static_cast<float>(x) + leaf.step_y * static_cast<float>(y);
}

// Algorithm 1 (or the configured rule) on the label half of a packed voxel, for a voxel the frame
// sees near its surface at depth pixel (ui, vi). Returns whether the label changed anything
// (false for ignored labels and non-positive or non-finite confidence).
inline bool applyPixelLabel(uint64_t& bits, PackedLabelSidecar* sidecar, const FrameView& frame, int ui, int vi,
                            const KernelConfig& config) {
  const int lu = frame.label_col[ui];
  const int lv = frame.label_row[vi];
  const LabelId observed = frame.labels[static_cast<std::size_t>(lv) * frame.label_stride + lu];
  const float w =
      frame.confidence ? frame.confidence[static_cast<std::size_t>(lv) * frame.confidence_stride + lu] : 1.0f;
  if ((*config.ignored)[observed] || !(w > 0.0f) || !std::isfinite(w)) return false;
  auto label = static_cast<LabelId>(bits >> 32);
  float score = halfValue(bits >> 48);
  applyLabelRule(config.label_rule, label, score, sidecar, observed, w);
  bits = (bits & uint64_t{0xFFFFFFFF}) | (uint64_t{label} << 32) | (uint64_t{halfBits(score)} << 48);
  return true;
}

// Updates the 512 voxels of one leaf from one frame, one voxel at a time. Each voxel reads the
// depth pixel it projects to (nearest pixel). kGeometry: TSDF/weight/colour update; kLabels:
// Algorithm 1. With only kLabels (late segmentation), voxels never observed are left alone.
template <bool kGeometry, bool kColor, bool kLabels>
KernelCounts updateLeafScalar(const LeafPair& leaf, const FrameView& frame, const KernelConfig& config) {
  KernelCounts counts;
  PackedVoxel* voxels = leaf.geometry->buffer().data();
  PackedColor* colors = kColor ? leaf.color->buffer().data() : nullptr;
  PackedLabelSidecar* sidecars = kLabels && leaf.label_sidecar ? leaf.label_sidecar->buffer().data() : nullptr;
  auto& active = leaf.geometry->getValueMask();
  const LeafInCamera cam = leafInCamera(*leaf.geometry, frame, config.voxel_size);
  const Eigen::Vector3f& step_z = cam.step_z;
  const float u_max = static_cast<float>(frame.width) - 0.5f;
  const float v_max = static_cast<float>(frame.height) - 0.5f;
  const auto depth_stride = static_cast<int>(frame.depth_stride);
  const float min_sdf = -config.truncation;

  for (int x = 0; x < kLeafDim; ++x) {
    // OpenVDB leaf order is z fastest, so the active bits of one x slab are one 64-bit mask word.
    uint64_t active_bits = 0;
    for (int y = 0; y < kLeafDim; ++y) {
      const Eigen::Vector3f p = columnStart(cam, x, y);
      const int row_offset = (x << 6) | (y << 3);
      // Project the column's 8 voxels and read their depth pixels in a branch-free loop the
      // compiler vectorises (the division and the tests dominate otherwise). Voxels behind the
      // camera or outside the image are marked row_of = -1.
      float depth_of[kLeafDim];
      int col_of[kLeafDim], row_of[kLeafDim];
      int inside = 0;
      for (int z = 0; z < kLeafDim; ++z) {
        const float fz = static_cast<float>(z);
        const float cz = p.z() + step_z.z() * fz;
        const float inv_z = 1.0f / cz;
        const float u = frame.fx * (p.x() + step_z.x() * fz) * inv_z + frame.cx;
        const float v = frame.fy * (p.y() + step_z.y() * fz) * inv_z + frame.cy;
        // Non-short-circuit & keeps the loop free of branches.
        const bool in_image = (cz > 0.0f) & (u >= -0.5f) & (u < u_max) & (v >= -0.5f) & (v < v_max);
        // Select before converting: float -> int of an out-of-range value is undefined.
        const int ui = static_cast<int>(in_image ? u + 0.5f : 0.0f);
        const int vi = static_cast<int>(in_image ? v + 0.5f : 0.0f);
        depth_of[z] = cz;
        col_of[z] = ui;
        row_of[z] = in_image ? vi : -1;
        inside |= static_cast<int>(in_image);
      }
      if (inside == 0) continue;
      for (int z = 0; z < kLeafDim; ++z) {
        const int vi = row_of[z];
        if (vi < 0) continue;
        const int ui = col_of[z];
        const float d = frame.depth[vi * depth_stride + ui];
        if (!frame.validDepth(d)) continue;
        const float sdf = d - depth_of[z];
        if (sdf < min_sdf) continue;  // far behind the surface: occluded, unknown

        const int offset = row_offset | z;
        // Work on the packed bits and convert only the half floats a branch changes: the label
        // half of the voxel is untouched by geometry updates and vice versa.
        uint64_t bits = static_cast<uint64_t>(voxels[offset]);
        if (kGeometry) {
          const float weight = halfValue(bits >> 16);
          const float observed = std::min(sdf, config.truncation);
          const float observed_weight = observationWeight(sdf, config);
          const float new_weight = weight + observed_weight;
          const float inv_new_weight = 1.0f / new_weight;  // one division for tsdf and colour
          const float tsdf = (halfValue(bits) * weight + observed * observed_weight) * inv_new_weight;
          if (kColor) {
            const uint8_t* rgb = frame.color + static_cast<std::size_t>(vi) * frame.color_stride + 3 * ui;
            const Rgb8 old = unpackColor(colors[offset]);
            auto blend = [&](uint8_t a, uint8_t b) {
              return static_cast<uint8_t>((a * weight + b * observed_weight) * inv_new_weight + 0.5f);
            };
            colors[offset] = packColor({blend(old.r, rgb[0]), blend(old.g, rgb[1]), blend(old.b, rgb[2])});
          }
          bits = (bits & ~uint64_t{0xFFFFFFFF}) | halfBits(tsdf) |
                 (uint64_t{halfBits(std::min(new_weight, config.max_weight))} << 16);
          ++counts.updated;
        } else if ((bits & 0xFFFF0000u) == 0) {
          continue;  // late labels only refine voxels that geometry has seen (weight > 0)
        }
        if (kLabels && sdf < config.truncation) {  // |d - z| < truncation: the frame sees this voxel
          PackedLabelSidecar* sidecar = sidecars ? sidecars + offset : nullptr;
          if (applyPixelLabel(bits, sidecar, frame, ui, vi, config)) ++counts.labeled;
        }
        voxels[offset] = static_cast<PackedVoxel>(bits);
        active_bits |= uint64_t{1} << ((y << 3) | z);
      }
    }
    active.template getWord<uint64_t>(static_cast<openvdb::Index>(x)) |= active_bits;
  }
  return counts;
}

// The AVX2 + F16C kernel (leaf_update_avx2.cpp): same contract and results as updateLeafScalar.
// Call only where avx2KernelSupported(frame) holds.
// Built for x86-64, the CPU has AVX2 + F16C, and the frame's offsets fit the int32 gather indices.
bool avx2KernelSupported(const FrameView& frame);
template <bool kGeometry, bool kColor, bool kLabels>
KernelCounts updateLeafAvx2(const LeafPair& leaf, const FrameView& frame, const KernelConfig& config);

}  // namespace semfuse::volume::detail
