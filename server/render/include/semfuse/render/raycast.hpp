#pragma once
// Raycasting a labeled volume from any pinhole camera: per pixel, find the first
// positive-to-non-positive zero crossing of the trilinear TSDF along the ray and read the layers
// there. A ray starts at the nearest block of surface cells projected onto its pixel and walks
// voxel cells, reading voxels only in cells whose corners change sign; bands of rows run in
// parallel with TBB. server/render/README.md has the details and the figures.
#include <cstdint>
#include <memory>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/raycast_layers.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render {

struct RaycastOptions {
  RaycastLayers layers = kDepthLayer | kNormalsLayer | kLabelsLayer;  // semfuse/core/raycast_layers.hpp
  double min_depth = 0.1;                                             // metres along the camera z axis
  double max_depth = 8.0;
  // Off: march every ray from min_depth (clipped to the allocated box) by samples, sphere-traced
  // in front of the surface, skipping nothing: the reference for benchmarks and tests (the images
  // agree to a hair; that march can miss a crossing that grazes a cell between two samples).
  bool skip_empty_space = true;
};

// Images of the requested layers; the others stay empty. `scores` is the kConfidenceLayer.
struct RaycastImages {
  cv::Mat depth;
  cv::Mat normals;
  cv::Mat labels;
  cv::Mat scores;
  cv::Mat color;
};

// Fails, naming the problem, on intrinsics that do not describe an image, a pose that is not
// rigid, a bad depth range, an empty layer mask or colour asked of a volume without colour.
Result<RaycastImages> raycast(const volume::LabeledVolume& volume, const PinholeIntrinsics& intrinsics,
                              const Pose& camera_to_world, const RaycastOptions& options = {});

// A raycast in two steps, for a volume that changes under a lock (the server's map):
// prepareRaycast() copies what the rays will read, the leaves in the camera's view and their
// upper neighbours (a few ms, under the caller's lock), and raycast(std::move(prepared)) renders
// from that copy, once, without touching the volume again. The images are those of raycast() at
// the time of the copy. (With skip_empty_space off the whole volume is copied.)
class PreparedRaycast {
 public:
  struct State;  // defined in raycast.cpp

 private:
  friend Result<PreparedRaycast> prepareRaycast(const volume::LabeledVolume&, const PinholeIntrinsics&, const Pose&,
                                                const RaycastOptions&);
  friend Result<RaycastImages> raycast(PreparedRaycast&&);
  std::shared_ptr<State> state_;
};

// Same checks and failures as raycast().
Result<PreparedRaycast> prepareRaycast(const volume::LabeledVolume& volume, const PinholeIntrinsics& intrinsics,
                                       const Pose& camera_to_world, const RaycastOptions& options = {});
Result<RaycastImages> raycast(PreparedRaycast&& prepared);

// The data-parallel kernels that run before the rays (reading the voxels of the leaves in view
// into crossing masks and float TSDF; the per-pixel depth bounds of each band of rows): AVX2 +
// F16C where the CPU has them (the default there), or portable. They give bit-identical images
// (tests/render/raycast_test.cpp); choosing one is for that test and for benchmarking.
// Process-wide; takes effect from the next raycast.
enum class RaycastKernel { kScalar, kAvx2 };
RaycastKernel raycastKernel();
bool raycastKernelAvailable(RaycastKernel kernel);    // kAvx2: built for x86-64 and the CPU has it
bool setRaycastKernel(RaycastKernel kernel);          // false, and no change, where unavailable
const char* raycastKernelName(RaycastKernel kernel);  // "scalar", "avx2"

}  // namespace semfuse::render
