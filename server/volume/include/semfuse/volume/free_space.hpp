#pragma once
// Observed free space. The TSDF holds only the truncation band around surfaces; a distance field
// or an occupancy map also needs to know which space a camera saw through and found empty, so
// that space nobody looked at stays unknown instead of passing for free.
//
// observeFreeSpace() marks the voxels a frame sees in front of its depth's truncation band: a
// voxel whose centre projects to a pixel with valid depth d (as the integrator projects) and lies
// nearer than d - truncation, where the projective TSDF would fuse +truncation. Candidates are the
// leaves that the rays of every 8th pixel of every 8th row cross between the camera's min_depth
// and d - truncation (a 3D DDA). A leaf whose whole box lies in front of the nearest depth of its
// image footprint minus the truncation (read from a min-depth pyramid over a rectangle covering
// the footprint, so the test errs towards unknown only) becomes a level-1 tile of the volume's
// FreeSpaceGrid (a MaskGrid) without looking at its voxels; the others are tested voxel by voxel
// and keep a mask leaf. Wholly free leaves are skipped from then on; the leaves that changed are
// stamped as changed (changesSince). Voxels behind every surface stay unknown.
#include <cstddef>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {

struct FreeSpaceStats {
  std::size_t candidate_leaves = 0;  // crossed by sampled rays and not yet wholly free
  std::size_t new_free_leaves = 0;   // of which wholly free from this frame on
  std::size_t new_free_voxels = 0;   // voxels of partly free leaves observed free by this frame
};

// depth CV_32FC1 metres with the volume's depth range (as integrate()); the pose camera-to-world.
// Errors as integrate() for bad images, intrinsics or poses; the volume is then unchanged.
//
// sample_stride > 1: in leaves the frame sees partly, only voxels whose three coordinates are
// multiples of it are tested and marked (wholly free leaves are still whole tiles). A distance
// field on voxels `sample_stride` times the map's reads nothing else (esdf::copyChanges), and the
// voxel-by-voxel test is most of the cost: at 1 cm with a 4 cm field it drops 64-fold.
Result<FreeSpaceStats> observeFreeSpace(LabeledVolume& volume, const cv::Mat& depth,
                                        const PinholeIntrinsics& intrinsics, const Pose& camera_to_world,
                                        int sample_stride = 1);

}  // namespace semfuse::volume
