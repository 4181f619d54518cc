#include "semfuse/volume/integrator.hpp"

#include <algorithm>
#include <atomic>
#include <bitset>
#include <cmath>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "band_leaves.hpp"
#include "frame_view.hpp"
#include "semfuse/volume/label_rules.hpp"

namespace semfuse::volume {
namespace {
using detail::FrameView;
using GeometryLeaf = GeometryGrid::TreeType::LeafNodeType;
using ColorLeaf = ColorGrid::TreeType::LeafNodeType;
using LabelSidecarLeaf = LabelSidecarGrid::TreeType::LeafNodeType;
constexpr int kLeafDim = static_cast<int>(GeometryLeaf::DIM);

// One leaf to update: its geometry and (when the volume has them) its colour and label-sidecar twins.
struct LeafPair {
  GeometryLeaf* geometry;
  ColorLeaf* color;
  LabelSidecarLeaf* label_sidecar = nullptr;
};

// Labels that never change a voxel: 0 and the background set. A bitset makes the per-voxel test
// one load instead of a search.
using IgnoredLabels = std::bitset<65536>;

std::unique_ptr<IgnoredLabels> ignoredLabels(const VolumeParams& params) {
  auto ignored = std::make_unique<IgnoredLabels>();
  ignored->set(kUnlabeled);
  for (LabelId id : params.background_labels) ignored->set(id);
  return ignored;
}

struct KernelConfig {
  float voxel_size;
  float truncation;
  float max_weight;
  float max_score;
  const IgnoredLabels* ignored;
  LabelRuleConfig label_rule;
};

struct KernelCounts {
  std::size_t updated = 0;
  std::size_t labeled = 0;
};

// Updates the 512 voxels of one leaf from one frame. Voxel camera coordinates are stepped
// incrementally from the leaf corner, and each voxel reads the depth pixel it projects to
// (nearest pixel). kGeometry: TSDF/weight/colour update; kLabels: Algorithm 1. With only kLabels
// (late segmentation), voxels never observed are left alone.
template <bool kGeometry, bool kColor, bool kLabels>
KernelCounts updateLeaf(const LeafPair& leaf, const FrameView& frame, const KernelConfig& config) {
  KernelCounts counts;
  PackedVoxel* voxels = leaf.geometry->buffer().data();
  PackedColor* colors = kColor ? leaf.color->buffer().data() : nullptr;
  auto& active = leaf.geometry->getValueMask();
  const openvdb::Coord origin = leaf.geometry->origin();
  const Eigen::Matrix3f& rotation = frame.world_to_camera_rotation;
  const Eigen::Vector3f corner =
      rotation * (Eigen::Vector3f(origin.x(), origin.y(), origin.z()) * config.voxel_size) +
      frame.world_to_camera_translation;
  const Eigen::Vector3f step_x = rotation.col(0) * config.voxel_size;
  const Eigen::Vector3f step_y = rotation.col(1) * config.voxel_size;
  const Eigen::Vector3f step_z = rotation.col(2) * config.voxel_size;
  const float u_max = static_cast<float>(frame.width) - 0.5f;
  const float v_max = static_cast<float>(frame.height) - 0.5f;
  const auto depth_stride = static_cast<int>(frame.depth_stride);
  const float min_sdf = -config.truncation;

  for (int x = 0; x < kLeafDim; ++x) {
    // OpenVDB leaf order is z fastest, so the active bits of one x slab are one 64-bit mask word.
    uint64_t active_bits = 0;
    for (int y = 0; y < kLeafDim; ++y) {
      const Eigen::Vector3f p = corner + step_x * static_cast<float>(x) + step_y * static_cast<float>(y);
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
          const float weight = volume::detail::halfValue(bits >> 16);
          const float observed = std::min(sdf, config.truncation);
          const float new_weight = weight + 1.0f;
          const float inv_new_weight = 1.0f / new_weight;  // one division for tsdf and colour
          const float tsdf = (volume::detail::halfValue(bits) * weight + observed) * inv_new_weight;
          if (kColor) {
            const uint8_t* rgb = frame.color + static_cast<std::size_t>(vi) * frame.color_stride + 3 * ui;
            const Rgb8 old = unpackColor(colors[offset]);
            auto blend = [&](uint8_t a, uint8_t b) {
              return static_cast<uint8_t>((a * weight + b) * inv_new_weight + 0.5f);
            };
            colors[offset] = packColor({blend(old.r, rgb[0]), blend(old.g, rgb[1]), blend(old.b, rgb[2])});
          }
          bits = (bits & ~uint64_t{0xFFFFFFFF}) | volume::detail::halfBits(tsdf) |
                 (uint64_t{volume::detail::halfBits(std::min(new_weight, config.max_weight))} << 16);
          ++counts.updated;
        } else if ((bits & 0xFFFF0000u) == 0) {
          continue;  // late labels only refine voxels that geometry has seen (weight > 0)
        }
        if (kLabels && sdf < config.truncation) {  // |d - z| < truncation: the frame sees this voxel
          const int lu = frame.label_col[ui];
          const int lv = frame.label_row[vi];
          const LabelId observed = frame.labels[static_cast<std::size_t>(lv) * frame.label_stride + lu];
          const float w = frame.confidence
                              ? frame.confidence[static_cast<std::size_t>(lv) * frame.confidence_stride + lu]
                              : 1.0f;
          if (!(*config.ignored)[observed] && w > 0.0f && std::isfinite(w)) {
            auto label = static_cast<LabelId>(bits >> 32);
            float score = volume::detail::halfValue(bits >> 48);
            PackedLabelSidecar* sidecar = leaf.label_sidecar ? leaf.label_sidecar->buffer().data() + offset : nullptr;
            applyLabelRule(config.label_rule, label, score, sidecar, observed, w);
            bits = (bits & uint64_t{0xFFFFFFFF}) | (uint64_t{label} << 32) |
                   (uint64_t{volume::detail::halfBits(score)} << 48);
            ++counts.labeled;
          }
        }
        voxels[offset] = static_cast<PackedVoxel>(bits);
        active_bits |= uint64_t{1} << ((y << 3) | z);
      }
    }
    active.template getWord<uint64_t>(static_cast<openvdb::Index>(x)) |= active_bits;
  }
  return counts;
}

template <bool kGeometry, bool kColor, bool kLabels>
void updateLeaves(const std::vector<LeafPair>& leaves, const FrameView& frame, const KernelConfig& config,
                  IntegrationStats& stats) {
  std::atomic<std::size_t> updated{0}, labeled{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      KernelCounts local;
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const KernelCounts c = updateLeaf<kGeometry, kColor, kLabels>(leaves[i], frame, config);
                        local.updated += c.updated;
                        local.labeled += c.labeled;
                      }
                      updated += local.updated;
                      labeled += local.labeled;
                    });
  stats.voxels_updated = updated;
  stats.voxels_labeled = labeled;
}

std::size_t countValidPixels(const FrameView& frame) {
  std::size_t n = 0;
  for (int v = 0; v < frame.height; ++v) {
    const float* row = frame.depth + static_cast<std::size_t>(v) * frame.depth_stride;
    for (int u = 0; u < frame.width; ++u) n += frame.validDepth(row[u]) ? 1 : 0;
  }
  return n;
}

KernelConfig kernelConfig(const VolumeParams& params, const IgnoredLabels* ignored) {
  return {static_cast<float>(params.voxel_size), static_cast<float>(params.truncation), params.max_weight,
          params.max_label_score, ignored, params.labelRuleConfig()};
}

}  // namespace

Result<IntegrationStats> integrate(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& color,
                                   const cv::Mat& labels, const cv::Mat& confidence,
                                   const PinholeIntrinsics& intrinsics, const Pose& camera_to_world) {
  const VolumeParams& params = volume.params();
  auto view = detail::makeFrameView(params, depth, color, labels, confidence, intrinsics, camera_to_world);
  if (!view) return makeError(view.error());
  const FrameView& frame = view.value();

  IntegrationStats stats;
  stats.valid_pixels = countValidPixels(frame);
  const std::vector<openvdb::Coord> origins =
      detail::bandLeafOrigins(frame, params.voxel_size, params.truncation);
  stats.leaves_touched = origins.size();

  // Allocation is serial: a few thousand leaves per frame, and OpenVDB trees are not safe to grow
  // concurrently. Colour leaves are created alongside so that both grids share one topology.
  std::vector<LeafPair> leaves;
  leaves.reserve(origins.size());
  auto geometry = volume.mutableGeometryGrid().getAccessor();
  ColorGrid* color_grid = volume.mutableColorGrid();
  std::unique_ptr<ColorGrid::Accessor> colors;
  if (color_grid) colors = std::make_unique<ColorGrid::Accessor>(color_grid->getAccessor());
  LabelSidecarGrid* sidecar_grid = volume.mutableLabelSidecarGrid();
  std::unique_ptr<LabelSidecarGrid::Accessor> sidecars;
  if (sidecar_grid) sidecars = std::make_unique<LabelSidecarGrid::Accessor>(sidecar_grid->getAccessor());
  for (const openvdb::Coord& origin : origins) {
    GeometryLeaf* leaf = geometry.probeLeaf(origin);
    if (!leaf) {
      leaf = geometry.touchLeaf(origin);
      ++stats.leaves_allocated;
    }
    leaves.push_back({leaf, colors ? colors->touchLeaf(origin) : nullptr,
                      sidecars ? sidecars->touchLeaf(origin) : nullptr});
  }

  const std::unique_ptr<IgnoredLabels> ignored = ignoredLabels(params);
  const KernelConfig config = kernelConfig(params, ignored.get());
  const bool with_color = color_grid && frame.color;
  const bool with_labels = frame.labels != nullptr;
  if (with_color && with_labels) updateLeaves<true, true, true>(leaves, frame, config, stats);
  else if (with_color) updateLeaves<true, true, false>(leaves, frame, config, stats);
  else if (with_labels) updateLeaves<true, false, true>(leaves, frame, config, stats);
  else updateLeaves<true, false, false>(leaves, frame, config, stats);

  volume.setFramesIntegrated(volume.framesIntegrated() + 1);
  return stats;
}

Result<IntegrationStats> integrate(LabeledVolume& volume, const Frame& frame, const Segmentation* segmentation) {
  if (!frame.camera_to_world) return makeError("frame " + std::to_string(frame.seq) + " carries no camera_to_world pose");
  if (segmentation)
    return integrate(volume, frame.depth, frame.color, segmentation->labels, segmentation->confidence,
                     frame.intrinsics, *frame.camera_to_world);
  return integrate(volume, frame.depth, frame.color, cv::Mat(), cv::Mat(), frame.intrinsics, *frame.camera_to_world);
}

Result<IntegrationStats> integrateLabels(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& labels,
                                         const cv::Mat& confidence, const PinholeIntrinsics& intrinsics,
                                         const Pose& camera_to_world) {
  if (labels.empty()) return makeError("labels: image is empty");
  const VolumeParams& params = volume.params();
  auto view = detail::makeFrameView(params, depth, cv::Mat(), labels, confidence, intrinsics, camera_to_world);
  if (!view) return makeError(view.error());
  const FrameView& frame = view.value();

  IntegrationStats stats;
  stats.valid_pixels = countValidPixels(frame);
  const std::vector<openvdb::Coord> origins =
      detail::bandLeafOrigins(frame, params.voxel_size, params.truncation);
  stats.leaves_touched = origins.size();
  std::vector<LeafPair> leaves;
  leaves.reserve(origins.size());
  auto geometry = volume.mutableGeometryGrid().getAccessor();
  LabelSidecarGrid* sidecar_grid = volume.mutableLabelSidecarGrid();
  for (const openvdb::Coord& origin : origins)
    if (GeometryLeaf* leaf = geometry.probeLeaf(origin))
      // Sidecar leaves were allocated with their geometry leaf (same topology), so touch finds them.
      leaves.push_back({leaf, nullptr, sidecar_grid ? sidecar_grid->tree().touchLeaf(origin) : nullptr});

  const std::unique_ptr<IgnoredLabels> ignored = ignoredLabels(params);
  updateLeaves<false, false, true>(leaves, frame, kernelConfig(params, ignored.get()), stats);
  return stats;
}

}  // namespace semfuse::volume
