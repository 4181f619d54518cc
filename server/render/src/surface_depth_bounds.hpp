#pragma once
// Per-pixel camera-depth bounds of where a surface can be, for raycast(). Internal.
//
// A ray can only report the surface inside a crossing cell (CrossingCells). Each 4^3 block of
// cells of a leaf that holds crossing cells is reduced to the tight box of those cells, the box is
// projected into the image, and every pixel centre its projection covers keeps the smallest and
// largest camera depth of the boxes over it. A ray then starts where the nearest box over its
// pixel begins and stops where the farthest ends: the free space in front of the surface needs
// no marching at all. Tight boxes rather than whole blocks: a block seen obliquely spans several
// voxels of depth in front of the surface it holds (a floor on the lowest voxel layer of a block
// would otherwise start its rays up to 4 voxels above it, 12 along a ray at 20 degrees).
//
// Conservative by construction (the projection of a box in front of the camera lies inside the
// rectangle of its projected corners); a box that reaches behind the camera plane opens every
// pixel from the near clip on. The rectangles are filed per band of image rows, and each band's
// per-pixel bounds are filled just before its rows are marched, by the thread that marches them.
#include <cstddef>
#include <vector>

#include "crossing_cells.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

// Per-pixel bounds of one band of image rows, filled by SurfaceDepthBounds::rasterizeBand. A
// band is small (its two buffers stay in cache while its rows are marched) and reused from band
// to band by the thread that marches them, so the bounds of a whole image are never held at once.
class BandBounds {
 public:
  // Camera-depth interval of pixel (u, v), v inside the band, that can hold a surface; false when
  // none can.
  bool depthRange(int u, int v, double& near, double& far) const {
    const std::size_t i = static_cast<std::size_t>(v - v_begin_) * width_ + u;
    if (!(near_[i] <= far_[i])) return false;
    near = near_[i];
    far = far_[i];
    return true;
  }

 private:
  friend class SurfaceDepthBounds;
  int v_begin_ = 0;
  int width_ = 0;
  std::vector<float> near_;  // +inf where no surface box covers the pixel
  std::vector<float> far_;   // -inf there
};

class SurfaceDepthBounds {
 public:
  static constexpr int kBandRows = 8;

  // Projects the blocks of crossing cells of `cells` (voxel size `voxel`) seen by
  // `camera_to_world` with intrinsics `k`, limited to [min_depth, max_depth]; parallel (TBB).
  SurfaceDepthBounds(const CrossingCells& cells, double voxel, const PinholeIntrinsics& k,
                     const Pose& camera_to_world, double min_depth, double max_depth);

  // Bands of kBandRows rows (the last may be shorter) cover the image.
  int bandCount() const { return (height_ + kBandRows - 1) / kBandRows; }
  // Fills `out` with the bounds of every pixel of rows [band * kBandRows, ... + kBandRows).
  void rasterizeBand(int band, BandBounds& out) const;

  // How many 4^3 blocks hold a crossing cell (for tests and benchmarks).
  std::size_t surfaceBlocks() const { return surface_blocks_; }

  struct Rect {  // inclusive pixel-centre rectangle of one projected box, with its depth interval
    int u0, u1, v0, v1;
    float near, far;
  };

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<Rect> footprints_;        // grouped by band: a rectangle is listed once per band it touches
  std::vector<std::size_t> band_start_;  // band b's rectangles: [band_start_[b], band_start_[b + 1])
  float open_near_ = 0.0f;               // every pixel's interval includes [open_near_, open_far_]
  float open_far_ = 0.0f;                // (empty, +inf > -inf, unless a box reaches behind the camera)
  std::size_t surface_blocks_ = 0;
};

}  // namespace semfuse::render::detail
