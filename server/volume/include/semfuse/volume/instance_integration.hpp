#pragma once
// Fusing a panoptic segmentation's instance map into the volume's instance evidence
// (instance_evidence.hpp), with the depth and pose of its frame.
//
// A segmenter's instance ids are its own: the pass first matches them to the map's. It projects
// every observed voxel near the frame's surface (|d - z| within two voxels and the truncation) of
// the leaves the frame's band touches into the instance map and counts, per segment, the voxels
// whose evidence names each map instance. Pairs are taken in order of that count, each segment and
// each map instance at most once, when the count is at least a third of the segment's voxels that
// name any instance and at least kMinInstanceVoxels: a segment that mostly covers voxels another
// frame called instance 7 is instance 7. A segment left without a match and large enough gets the
// next map id. The map instances of the frame's segments (its kMaxSegmentsSeenApart largest) are
// recorded as seen apart, two by two (LabeledVolume::instancesSeenApart). Then every such voxel adds one observation of
// its segment's map instance (the evidence rule of instance_evidence.hpp). Pixels without an instance (0) or with an
// ignored label (unlabeled, background) change nothing. Allocates instance leaves, never geometry leaves; stamps the
// leaves whose evidence changed with a new revision (LabeledVolume::markChanged).
#include <cstddef>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {

// Fewer voxels than this do not make or match an instance.
inline constexpr std::size_t kMinInstanceVoxels = 8;
// The instances of at most this many of a frame's largest segments are recorded as seen apart.
inline constexpr std::size_t kMaxSegmentsSeenApart = 128;

struct InstanceStats {
  std::size_t segments = 0;        // segments of the frame that covered enough voxels
  std::size_t matched = 0;         // of which matched to a map instance
  std::size_t created = 0;         // of which given a new map instance
  std::size_t voxels_updated = 0;  // voxels whose evidence changed
};

// instances: CV_16UC1 of the labels' size (0 = no instance); labels as integrate() takes them.
Result<InstanceStats> integrateInstances(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& labels,
                                         const cv::Mat& instances, const PinholeIntrinsics& intrinsics,
                                         const Pose& camera_to_world);

}  // namespace semfuse::volume
