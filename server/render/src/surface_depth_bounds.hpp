#pragma once
// Per-pixel camera-depth bounds of where a surface can be, for raycast(). Internal.
//
// A ray can only report the surface inside a crossing cell (CrossingCells), at a point where the
// trilinear TSDF is <= 0. Each 2^3 block of cells of a leaf that holds crossing cells is reduced
// to a box and a half-space that hold those points (CrossingCells::surfaceBoxes(): the box from
// the cells' edges, the half-space along the surface), and every pixel whose ray passes through
// both keeps the smallest depth at which its ray enters such a region and the largest at which it
// leaves one. A ray then walks only from the first entry to the last exit: neither the free space
// in front of the surface nor, mostly, the positive side of the crossing cells just in front of it.
//
// Each box is projected to the rectangle of its projected corners and filed per band of image
// rows; just before a band is marched, the thread that marches it intersects each pixel's ray in
// the rectangles over it with the box and half-space (three slabs, from per-pixel inverse ray
// directions, and one plane: a few vector operations per pixel). Conservative by construction
// (up to float rounding, which the margins absorb); a box that reaches behind the camera plane
// opens every pixel from the near clip on.
#include <cstddef>
#include <vector>

#include "crossing_cells.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

// Per-pixel bounds of one band of image rows, filled by SurfaceDepthBounds::rasterizeBand. A
// band is small (its buffers stay in cache while its rows are marched) and reused from band
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
  std::vector<float> near_;               // +inf where no surface box covers the pixel
  std::vector<float> far_;                // -inf there
  std::vector<float> inverse_direction_;  // scratch of rasterizeBand: per world axis, per pixel
};

class SurfaceDepthBounds {
 public:
  static constexpr int kBandRows = 8;

  // Projects the surface boxes of `cells` (findCrossings() done; voxel size `voxel`) seen by
  // `camera_to_world` with intrinsics `k`, limited to [min_depth, max_depth]; parallel (TBB).
  SurfaceDepthBounds(const CrossingCells& cells, double voxel, const PinholeIntrinsics& k, const Pose& camera_to_world,
                     double min_depth, double max_depth);

  // Bands of kBandRows rows (the last may be shorter) cover the image.
  int bandCount() const { return (height_ + kBandRows - 1) / kBandRows; }
  // Fills `out` with the bounds of every pixel of rows [band * kBandRows, ... + kBandRows).
  void rasterizeBand(int band, BandBounds& out) const;

  struct Rect {  // inclusive pixel-centre rectangle of one projected box, and the box itself
    int u0, u1, v0, v1;
    float low[3], high[3];  // world box minus the camera centre, metres
    // Its half-space along pixel (u, v)'s ray at camera depth t: t a <= plane_c, with
    // a = plane_du u + plane_dv v + plane_at_origin.
    float plane_du, plane_dv, plane_at_origin, plane_c;
  };

  // One band's buffers as the per-pixel loops of rasterizeBand see them: `rows` rows of `width`
  // pixels from row v_begin, each buffer padded by kBandPadding floats so that 8-lane loads and
  // stores may run past a row's last pixel.
  static constexpr int kBandPadding = 8;
  struct BandView {
    int v_begin, rows, width;
    float* near;
    float* far;
    float* inverse_direction;  // per world axis, `rows * width` floats
    float near_margin, far_margin;
    std::size_t pixels() const { return static_cast<std::size_t>(rows) * width; }
  };

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<Rect> footprints_;         // grouped by band: a rectangle is listed once per band it touches
  std::vector<std::size_t> band_start_;  // band b's rectangles: [band_start_[b], band_start_[b + 1])
  float open_near_ = 0.0f;               // every pixel's interval includes [open_near_, open_far_]
  float open_far_ = 0.0f;                // (empty, +inf > -inf, unless a box reaches behind the camera)
  float near_margin_ = 0.0f, far_margin_ = 0.0f;
  // Pixel (u, v)'s ray direction per unit of camera depth, world frame: du u + dv v + at_origin.
  double ray_du_[3] = {}, ray_dv_[3] = {}, ray_at_origin_[3] = {};
};

namespace bounds_constants {
// Inverse ray direction components are clamped to this (a zero component gives +-inf, and 0 x inf
// would be NaN in the slab test).
constexpr float kHugeInverse = 1e12f;
// Smallest |slope| of a ray against a half-space (TSDF metres per metre of depth): a ray that
// runs parallel to the plane then meets it beyond any depth, or never leaves it.
constexpr float kTinySlope = 1e-12f;
// Added to the near bound (and taken from the far bound) of a ray that misses a box.
constexpr float kBeyondAnyDepth = 1e30f;
}  // namespace bounds_constants

// rasterizeBand's two loops over pixels: the rays' inverse direction components, then each
// rectangle of the band clipping its pixels' rays. The AVX2 versions (surface_depth_bounds_avx2.cpp;
// only where raycastKernel() is kAvx2) compute the same floats in 8 lanes: the same operations in
// the same order, no fused multiply-add.
void fillInverseDirections(const SurfaceDepthBounds::BandView& band, const double ray_du[3], const double ray_dv[3],
                           const double ray_at_origin[3]);
void fillInverseDirectionsAvx2(const SurfaceDepthBounds::BandView& band, const double ray_du[3], const double ray_dv[3],
                               const double ray_at_origin[3]);
void clipRects(const SurfaceDepthBounds::BandView& band, const SurfaceDepthBounds::Rect* first,
               const SurfaceDepthBounds::Rect* last);
void clipRectsAvx2(const SurfaceDepthBounds::BandView& band, const SurfaceDepthBounds::Rect* first,
                   const SurfaceDepthBounds::Rect* last);

}  // namespace semfuse::render::detail
