#pragma once
// Internal: which leaves the truncation band of a depth image touches, and which leaves its rays
// cross in front of the band.
#include <vector>

#include <openvdb/openvdb.h>

#include "frame_view.hpp"

namespace semfuse::volume::detail {

// Pixel stride of the leaf search. Leaves are 8 voxels (8 cm at 1 cm voxels) wide while a stride
// of 4 pixels spans under 2 cm at the 1-3 m of indoor RGB-D (f ~ 585): every leaf the band covers
// over more than a thin sliver at its edge contains at least one sampled ray. The voxels of such
// a sliver miss this frame's update only; neighbouring views fill them in. A 16x cheaper search
// for that is the point: searching every pixel costs as much as the whole voxel update.
inline constexpr int kBandSearchPixelStride = 4;

// Origins of the leaves that contain a point of the band [d - truncation, d + truncation] along
// the ray of a sampled valid pixel, in tree order (spatially coherent). Parallel over image rows.
std::vector<openvdb::Coord> bandLeafOrigins(const FrameView& frame, double voxel_size, double truncation,
                                            int pixel_stride = kBandSearchPixelStride);

// Origins of the leaves that the rays of sampled valid pixels cross in front of the band, from
// the camera's min_depth to d - truncation: the candidates for observed free space.
std::vector<openvdb::Coord> freeSpaceLeafOrigins(const FrameView& frame, double voxel_size, double truncation,
                                                 int pixel_stride);

}  // namespace semfuse::volume::detail
