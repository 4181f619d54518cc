#include "semfuse/volume/integrator.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "band_leaves.hpp"
#include "frame_view.hpp"
#include "leaf_update.hpp"

namespace semfuse::volume {
namespace {
using detail::FrameView;
using detail::GeometryLeaf;
using detail::IgnoredLabels;
using detail::KernelConfig;
using detail::KernelCounts;
using detail::LeafPair;

// The widest kernel this CPU runs, unless setIntegrationKernel() chose another; read once per call.
std::atomic<IntegrationKernel> g_kernel{
    integrationKernelAvailable(IntegrationKernel::kAvx2) ? IntegrationKernel::kAvx2 : IntegrationKernel::kScalar};

template <bool kGeometry, bool kColor, bool kLabels>
void updateLeaves(const std::vector<LeafPair>& leaves, const FrameView& frame, const KernelConfig& config,
                  const BetweenBatches& between_batches, IntegrationStats& stats) {
  // The kernel is chosen per frame, not per leaf: one branch per call instead of per leaf.
  const bool wide =
      g_kernel.load(std::memory_order_relaxed) == IntegrationKernel::kAvx2 && detail::avx2KernelSupported(frame);
  const auto update_leaf = wide ? &detail::updateLeafAvx2<kGeometry, kColor, kLabels>
                                : &detail::updateLeafScalar<kGeometry, kColor, kLabels>;
  std::atomic<std::size_t> updated{0}, labeled{0};
  // One batch at once when nobody waits between batches: the pauses cost nothing then.
  const std::size_t batch = between_batches ? kLeavesPerBatch : std::max<std::size_t>(leaves.size(), 1);
  for (std::size_t first = 0; first < leaves.size(); first += batch) {
    if (first > 0) between_batches();
    const std::size_t last = std::min(leaves.size(), first + batch);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        KernelCounts local;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          const KernelCounts c = update_leaf(leaves[i], frame, config);
                          local.updated += c.updated;
                          local.labeled += c.labeled;
                        }
                        updated += local.updated;
                        labeled += local.labeled;
                      });
  }
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
  const double dropoff_start = params.weight_dropoff * params.truncation;
  // A drop-off at the truncation itself is no drop-off: every observation weighs 1.
  const double dropoff_per_metre = params.weight_dropoff < 1.0f ? 1.0 / (params.truncation - dropoff_start) : 0.0;
  return {static_cast<float>(params.voxel_size),
          static_cast<float>(params.truncation),
          static_cast<float>(dropoff_start),
          static_cast<float>(dropoff_per_metre),
          params.max_weight,
          params.max_label_score,
          ignored,
          params.labelRuleConfig()};
}

}  // namespace

Result<IntegrationStats> integrate(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& color,
                                   const cv::Mat& labels, const cv::Mat& confidence,
                                   const PinholeIntrinsics& intrinsics, const Pose& camera_to_world,
                                   const BetweenBatches& between_batches) {
  const VolumeParams& params = volume.params();
  auto view = detail::makeFrameView(params, depth, color, labels, confidence, intrinsics, camera_to_world);
  if (!view) return makeError(view.error());
  const FrameView& frame = view.value();

  IntegrationStats stats;
  stats.valid_pixels = countValidPixels(frame);
  const std::vector<openvdb::Coord> origins = detail::bandLeafOrigins(frame, params.voxel_size, params.truncation);
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
    leaves.push_back(
        {leaf, colors ? colors->touchLeaf(origin) : nullptr, sidecars ? sidecars->touchLeaf(origin) : nullptr});
  }

  const std::unique_ptr<IgnoredLabels> ignored = detail::ignoredLabels(params);
  const KernelConfig config = kernelConfig(params, ignored.get());
  const bool with_color = color_grid && frame.color;
  const bool with_labels = frame.labels != nullptr;
  if (with_color && with_labels) updateLeaves<true, true, true>(leaves, frame, config, between_batches, stats);
  else if (with_color) updateLeaves<true, true, false>(leaves, frame, config, between_batches, stats);
  else if (with_labels) updateLeaves<true, false, true>(leaves, frame, config, between_batches, stats);
  else updateLeaves<true, false, false>(leaves, frame, config, between_batches, stats);

  volume.markChanged(origins);
  volume.setFramesIntegrated(volume.framesIntegrated() + 1);
  return stats;
}

Result<IntegrationStats> integrate(LabeledVolume& volume, const Frame& frame, const Segmentation* segmentation,
                                   const BetweenBatches& between_batches) {
  if (!frame.camera_to_world)
    return makeError("frame " + std::to_string(frame.seq) + " carries no camera_to_world pose");
  if (segmentation)
    return integrate(volume, frame.depth, frame.color, segmentation->labels, segmentation->confidence, frame.intrinsics,
                     *frame.camera_to_world, between_batches);
  return integrate(volume, frame.depth, frame.color, cv::Mat(), cv::Mat(), frame.intrinsics, *frame.camera_to_world,
                   between_batches);
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
  const std::vector<openvdb::Coord> origins = detail::bandLeafOrigins(frame, params.voxel_size, params.truncation);
  stats.leaves_touched = origins.size();
  std::vector<LeafPair> leaves;
  leaves.reserve(origins.size());
  std::vector<openvdb::Coord> labeled;
  labeled.reserve(origins.size());
  auto geometry = volume.mutableGeometryGrid().getAccessor();
  LabelSidecarGrid* sidecar_grid = volume.mutableLabelSidecarGrid();
  for (const openvdb::Coord& origin : origins)
    if (GeometryLeaf* leaf = geometry.probeLeaf(origin)) {
      // Sidecar leaves were allocated with their geometry leaf (same topology), so touch finds them.
      leaves.push_back({leaf, nullptr, sidecar_grid ? sidecar_grid->tree().touchLeaf(origin) : nullptr});
      labeled.push_back(origin);
    }

  const std::unique_ptr<IgnoredLabels> ignored = detail::ignoredLabels(params);
  updateLeaves<false, false, true>(leaves, frame, kernelConfig(params, ignored.get()), {}, stats);
  volume.markChanged(labeled);
  return stats;
}

IntegrationKernel integrationKernel() { return g_kernel.load(); }

bool setIntegrationKernel(IntegrationKernel kernel) {
  if (kernel == IntegrationKernel::kAvx2 && !integrationKernelAvailable(kernel)) return false;
  g_kernel.store(kernel);
  return true;
}

bool integrationKernelAvailable(IntegrationKernel kernel) {
  if (kernel == IntegrationKernel::kScalar) return true;
  // Any frame wide enough for the kernel answers for the CPU.
  detail::FrameView probe;
  probe.width = 2;
  probe.height = 1;
  return detail::avx2KernelSupported(probe);
}

const char* integrationKernelName(IntegrationKernel kernel) {
  return kernel == IntegrationKernel::kAvx2 ? "avx2" : "scalar";
}

}  // namespace semfuse::volume
