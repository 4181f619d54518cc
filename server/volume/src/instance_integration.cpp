#include "semfuse/volume/instance_integration.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "band_leaves.hpp"
#include "frame_view.hpp"
#include "leaf_update.hpp"

namespace semfuse::volume {
namespace {

using detail::FrameView;
using detail::GeometryLeaf;
using InstanceLeaf = InstanceGrid::TreeType::LeafNodeType;

// The frame's instance map, read like its labels (label_col / label_row map depth pixels to it).
struct InstanceView {
  const uint16_t* data;
  std::size_t stride;  // in elements
  uint16_t at(const FrameView& frame, int ui, int vi) const {
    return data[static_cast<std::size_t>(frame.label_row[vi]) * stride + frame.label_col[ui]];
  }
};

// Calls fn(offset, segment) for every observed voxel of the leaf that the frame sees within `band`
// of its surface, at a pixel with an instance and a label that counts.
template <class Fn>
void visitSegmentedVoxels(const GeometryLeaf& leaf, const FrameView& frame, const InstanceView& instances,
                          const detail::IgnoredLabels& ignored, float voxel_size, float band, Fn&& fn) {
  const detail::LeafInCamera cam = detail::leafInCamera(leaf, frame, voxel_size);
  const float u_max = static_cast<float>(frame.width) - 0.5f;
  const float v_max = static_cast<float>(frame.height) - 0.5f;
  for (auto it = leaf.cbeginValueOn(); it; ++it) {
    if (!isObserved(*it)) continue;
    const openvdb::Index n = it.pos();
    const float x = float(n >> 6), y = float((n >> 3) & 7), z = float(n & 7);
    const Eigen::Vector3f p = cam.corner + cam.step_x * x + cam.step_y * y + cam.step_z * z;
    if (!(p.z() > 0.0f)) continue;
    const float u = frame.fx * p.x() / p.z() + frame.cx;
    const float v = frame.fy * p.y() / p.z() + frame.cy;
    if (!(u >= -0.5f && u < u_max && v >= -0.5f && v < v_max)) continue;
    const int ui = static_cast<int>(u + 0.5f), vi = static_cast<int>(v + 0.5f);
    const float d = frame.depth[static_cast<std::size_t>(vi) * frame.depth_stride + ui];
    if (!frame.validDepth(d) || std::abs(d - p.z()) >= band) continue;
    const LabelId label =
        frame.labels[static_cast<std::size_t>(frame.label_row[vi]) * frame.label_stride + frame.label_col[ui]];
    if (ignored[label]) continue;
    const uint16_t segment = instances.at(frame, ui, vi);
    if (segment != 0) fn(n, segment);
  }
}

uint64_t pairKey(uint16_t segment, uint32_t instance) { return uint64_t{segment} << 32 | instance; }

}  // namespace

Result<InstanceStats> integrateInstances(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& labels,
                                         const cv::Mat& instances, const PinholeIntrinsics& intrinsics,
                                         const Pose& camera_to_world) {
  if (labels.empty()) return makeError("labels: image is empty");
  if (instances.type() != CV_16UC1 || instances.size() != labels.size())
    return makeError("instances: must be CV_16UC1 of the labels' size (" + std::to_string(labels.cols) + "x" +
                     std::to_string(labels.rows) + ")");
  const VolumeParams& params = volume.params();
  auto view = detail::makeFrameView(params, depth, cv::Mat(), labels, cv::Mat(), intrinsics, camera_to_world);
  if (!view) return makeError(view.error());
  const FrameView& frame = view.value();
  const InstanceView instance_view{instances.ptr<uint16_t>(), instances.step1()};
  const std::unique_ptr<detail::IgnoredLabels> ignored = detail::ignoredLabels(params);
  const float voxel = static_cast<float>(params.voxel_size);
  const float band = std::min(2.0f * voxel, static_cast<float>(params.truncation));

  std::vector<const GeometryLeaf*> leaves;
  const auto& geometry = volume.geometryGrid().tree();
  for (const openvdb::Coord& origin : detail::bandLeafOrigins(frame, params.voxel_size, params.truncation))
    if (const GeometryLeaf* leaf = geometry.probeConstLeaf(origin)) leaves.push_back(leaf);

  // 1. Per (segment, map instance): voxels. Map instance 0: voxels without evidence.
  const InstanceGrid* grid = volume.instanceGrid();
  tbb::combinable<std::unordered_map<uint64_t, uint32_t>> counted;
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t l) {
    const InstanceLeaf* evidence = grid ? grid->tree().probeConstLeaf(leaves[l]->origin()) : nullptr;
    auto& counts = counted.local();
    visitSegmentedVoxels(*leaves[l], frame, instance_view, *ignored, voxel, band, [&](openvdb::Index n, uint16_t s) {
      const PackedInstance packed = evidence ? evidence->getValue(n) : 0;
      ++counts[pairKey(s, instanceEvidenceOf(packed) > 0 ? instanceIdOf(packed) : 0)];
    });
  });
  std::unordered_map<uint64_t, uint32_t> counts;
  counted.combine_each([&](const auto& local) {
    for (const auto& [key, count] : local) counts[key] += count;
  });

  // 2. Segments to map instances.
  std::unordered_map<uint16_t, std::pair<uint32_t, uint32_t>> segment_voxels;  // (all, naming an instance)
  std::vector<std::tuple<uint32_t, uint16_t, uint32_t>> pairs;                 // (voxels, segment, instance)
  for (const auto& [key, count] : counts) {
    const auto segment = static_cast<uint16_t>(key >> 32);
    const auto instance = static_cast<uint32_t>(key & 0xFFFFFFFFu);
    segment_voxels[segment].first += count;
    if (instance != 0) {
      segment_voxels[segment].second += count;
      pairs.emplace_back(count, segment, instance);
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a > b; });
  std::vector<uint32_t> instance_of(65536, 0);
  std::unordered_map<uint32_t, bool> taken;
  InstanceStats stats;
  for (const auto& [count, segment, instance] : pairs) {
    if (instance_of[segment] != 0 || taken.count(instance)) continue;
    // Most of what the segment covers and the map has named, and a fair part of all it covers:
    // an object seen for the first time touches its neighbours' named voxels only at its rim.
    const auto& [all, named] = segment_voxels[segment];
    if (count < kMinInstanceVoxels || 3 * count < named || 6 * count < all) continue;
    instance_of[segment] = instance;
    taken[instance] = true;
    ++stats.matched;
  }
  for (const auto& [segment, voxels] : segment_voxels) {
    if (voxels.first < kMinInstanceVoxels) continue;
    ++stats.segments;
    if (instance_of[segment] != 0) continue;
    if (volume.nextInstanceId() > kMaxInstanceId) continue;  // ids exhausted: no new instances
    instance_of[segment] = volume.nextInstanceId();
    volume.setNextInstanceId(volume.nextInstanceId() + 1);
    ++stats.created;
  }
  // The segments' instances are two by two different objects: the largest segments' pairs, so
  // that a map cut into thousands of segments costs bounded time and memory.
  std::vector<std::pair<uint32_t, uint32_t>> seen;  // (voxels, map instance)
  for (const auto& [segment, voxels] : segment_voxels)
    if (instance_of[segment] != 0) seen.emplace_back(voxels.first, instance_of[segment]);
  std::sort(seen.begin(), seen.end(), [](const auto& a, const auto& b) { return a > b; });
  seen.resize(std::min(seen.size(), kMaxSegmentsSeenApart));
  std::vector<uint64_t> apart;
  for (std::size_t i = 0; i < seen.size(); ++i)
    for (std::size_t j = i + 1; j < seen.size(); ++j) apart.push_back(instancePairKey(seen[i].second, seen[j].second));
  volume.markInstancesSeenApart(std::move(apart));

  // 3. Evidence. Instance leaves are allocated serially, then updated in parallel.
  InstanceGrid& writable = volume.mutableInstanceGrid();
  std::vector<InstanceLeaf*> evidence_leaves(leaves.size());
  for (std::size_t l = 0; l < leaves.size(); ++l) evidence_leaves[l] = writable.tree().touchLeaf(leaves[l]->origin());
  std::atomic<std::size_t> updated{0};
  std::vector<uint8_t> leaf_changed(leaves.size(), 0);
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t l) {
    InstanceLeaf& evidence = *evidence_leaves[l];
    std::size_t local = 0;
    visitSegmentedVoxels(*leaves[l], frame, instance_view, *ignored, voxel, band, [&](openvdb::Index n, uint16_t s) {
      const uint32_t observed = instance_of[s];
      if (observed == 0) return;
      const PackedInstance packed = evidence.getValue(n);
      const uint32_t id = instanceIdOf(packed), count = instanceEvidenceOf(packed);
      PackedInstance next;
      if (count == 0 || id == observed) next = packInstance(observed, std::min(count + 1, kMaxInstanceEvidence));
      else if (count > 1) next = packInstance(id, count - 1);
      else next = packInstance(observed, 1);
      evidence.setValueOn(n, next);
      ++local;
    });
    updated += local;
    leaf_changed[l] = local > 0;
  });
  stats.voxels_updated = updated;
  // A write like any other: consumers of the map's changes (the objects' surface cache) see it.
  std::vector<openvdb::Coord> changed;
  for (std::size_t l = 0; l < leaves.size(); ++l)
    if (leaf_changed[l]) changed.push_back(leaves[l]->origin());
  if (!changed.empty()) volume.markChanged(changed);
  return stats;
}

}  // namespace semfuse::volume
