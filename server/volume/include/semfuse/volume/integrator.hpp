#pragma once
// Projective integration of depth (+ colour, + labels) into a LabeledVolume, parallel over leaves:
//  1. allocate the leaves that the truncation band of the new depth map touches;
//  2. update every voxel of those leaves by projecting it into the image: running weighted TSDF
//     average clamped at max_weight, colour running average, and label evidence (Algorithm 1 of
//     Cavallari & Di Stefano, PSIVT 2015) where a segmentation comes with the frame.
// integrateLabels() applies a segmentation that arrives later with the depth and pose of its own
// frame, leaving geometry untouched.
//
// Images: depth CV_32FC1 metres (0, NaN, or outside [min_depth, max_depth] = invalid);
// colour CV_8UC3 RGB of the depth's size (optional: empty Mat); labels CV_16UC1 (0 = unlabeled)
// and confidence CV_32FC1 of the labels' size, which may be smaller than the depth (nearest-
// neighbour upsampled); an empty confidence counts every labeled pixel with confidence 1.
// Every input is checked first; a bad one gives an error naming it and the volume is unchanged.
//
// `between_batches`, when given, is called from the calling thread between batches of leaves
// (kLeavesPerBatch each), the volume's topology fixed and every voxel whole: a caller that holds
// the map exclusively may let readers look there (the server lets tracking in); none may write.
#include <cstddef>
#include <functional>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {

struct IntegrationStats {
  std::size_t valid_pixels = 0;      // depth pixels within range
  std::size_t leaves_touched = 0;    // leaves in the truncation band of this frame
  std::size_t leaves_allocated = 0;  // of which new
  std::size_t voxels_updated = 0;    // voxels whose TSDF was updated
  std::size_t voxels_labeled = 0;    // voxels where Algorithm 1 ran (label not 0/background)
};

using BetweenBatches = std::function<void()>;
inline constexpr std::size_t kLeavesPerBatch = 512;

Result<IntegrationStats> integrate(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& color,
                                   const cv::Mat& labels, const cv::Mat& confidence,
                                   const PinholeIntrinsics& intrinsics, const Pose& camera_to_world,
                                   const BetweenBatches& between_batches = {});

// Depth (+ colour) only.
inline Result<IntegrationStats> integrate(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& color,
                                          const PinholeIntrinsics& intrinsics, const Pose& camera_to_world) {
  return integrate(volume, depth, color, cv::Mat(), cv::Mat(), intrinsics, camera_to_world);
}

// A decoded frame (which must carry its camera_to_world pose), optionally with its segmentation.
Result<IntegrationStats> integrate(LabeledVolume& volume, const Frame& frame,
                                   const Segmentation* segmentation = nullptr,
                                   const BetweenBatches& between_batches = {});

// Label evidence only, for a segmentation that arrives after its frame was integrated: the
// voxels that frame saw near the surface, with that frame's depth and pose. Allocates nothing.
Result<IntegrationStats> integrateLabels(LabeledVolume& volume, const cv::Mat& depth, const cv::Mat& labels,
                                         const cv::Mat& confidence, const PinholeIntrinsics& intrinsics,
                                         const Pose& camera_to_world);

// The per-voxel update exists twice: portable scalar code and an AVX2 + F16C version (8 voxels
// of a leaf column per instruction) for x86-64 CPUs that have both, the default where available.
// They give bit-identical volumes (tests/volume/integrate_kernels_test.cpp); choosing one is for
// that test and for benchmarking. Process-wide; takes effect from the next integrate() call.
enum class IntegrationKernel { kScalar, kAvx2 };
IntegrationKernel integrationKernel();
bool integrationKernelAvailable(IntegrationKernel kernel);    // kAvx2: built for x86-64 and the CPU has it
bool setIntegrationKernel(IntegrationKernel kernel);          // false, and no change, where unavailable
const char* integrationKernelName(IntegrationKernel kernel);  // "scalar", "avx2"

}  // namespace semfuse::volume
