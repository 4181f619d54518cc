#pragma once
// The label error metrics of the experiments.
//  volumetric: over the surface voxels (the zero-level isosurface: observed voxels with an
//    observed 6-neighbour of the opposite TSDF sign) that the reference labels, the fraction whose
//    label differs from the reference's (unlabeled counts as wrong).
//  per-frame: over the pixels a reference image labels, the fraction labeled differently.
#include <cstddef>
#include <vector>

#include <openvdb/openvdb.h>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::eval {

struct LabelError {
  std::size_t compared = 0;  // voxels or pixels the reference labels
  std::size_t wrong = 0;
  double fraction() const { return compared == 0 ? 0.0 : static_cast<double>(wrong) / compared; }
};

// Surface voxels of a volume, in tree order.
std::vector<openvdb::Coord> surfaceVoxels(const volume::LabeledVolume& volume);

// Volumetric error of `test` against `reference` on the given voxels (from surfaceVoxels of the
// reference; the two volumes normally share their geometry).
LabelError volumetricLabelError(const volume::LabeledVolume& reference, const volume::LabeledVolume& test,
                                const std::vector<openvdb::Coord>& voxels);

// Per-frame error of a CV_16UC1 label image against a reference image of the same size.
Result<LabelError> pixelLabelError(const cv::Mat& reference, const cv::Mat& labels);

}  // namespace semfuse::eval
