#include "surface_depth_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "semfuse/render/raycast.hpp"

namespace semfuse::render::detail {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Camera depth below which a corner counts as "at or behind the camera plane": its projection is
// unbounded, so the box cannot be reduced to a pixel rectangle.
constexpr double kMinProjectableDepth = 1e-6;
// The boxes are exact; the margins (voxels) only absorb rounding: of the float boxes, slabs and
// depths here, and of the rays' values along their cells (double, from float corners).
constexpr double kNearMarginVoxels = 0.05;
constexpr double kFarMarginVoxels = 0.05;
using bounds_constants::kBeyondAnyDepth;
using bounds_constants::kHugeInverse;
using bounds_constants::kTinySlope;

// What the blocks seen by one thread contribute: inclusive rectangles of pixel centres with their
// boxes, and the far end of the boxes that reach behind the camera plane (they cannot
// be projected and open every pixel).
struct Footprints {
  std::vector<SurfaceDepthBounds::Rect> rects;
  float behind_camera_far = -kInf;
};

}  // namespace

SurfaceDepthBounds::SurfaceDepthBounds(const CrossingCells& cells, double voxel, const PinholeIntrinsics& k,
                                       const Pose& camera_to_world, double min_depth, double max_depth)
    : width_(k.width), height_(k.height) {
  const double s = voxel;
  const double near_margin = kNearMarginVoxels * s, far_margin = kFarMarginVoxels * s;
  const Eigen::Matrix3d world_to_camera = camera_to_world.linear().transpose();
  const Eigen::Vector3d camera_origin = camera_to_world.translation();
  // Camera-frame unit edges of a box.
  const Eigen::Vector3d ex = world_to_camera.col(0) * s, ey = world_to_camera.col(1) * s,
                        ez = world_to_camera.col(2) * s;

  // The world direction of pixel (u, v)'s ray, per unit of camera depth, is linear in u and v.
  const Eigen::Matrix3d& rotation = camera_to_world.linear();
  for (int a = 0; a < 3; ++a) {
    ray_du_[a] = rotation(a, 0) / k.fx;
    ray_dv_[a] = rotation(a, 1) / k.fy;
    ray_at_origin_[a] = rotation(a, 2) - rotation(a, 0) * k.cx / k.fx - rotation(a, 1) * k.cy / k.fy;
  }
  const Eigen::Vector3d ray_du(ray_du_[0], ray_du_[1], ray_du_[2]), ray_dv(ray_dv_[0], ray_dv_[1], ray_dv_[2]),
      ray_at_origin(ray_at_origin_[0], ray_at_origin_[1], ray_at_origin_[2]);

  const std::vector<SurfaceBox>& boxes = cells.surfaceBoxes();
  tbb::enumerable_thread_specific<Footprints> per_thread;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), 1024), [&](const auto& range) {
    Footprints& out = per_thread.local();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const SurfaceBox& box = boxes[i];
      Rect r{};
      for (int a = 0; a < 3; ++a) {
        r.low[a] = static_cast<float>(box.lo[a] * s - camera_origin[a]);
        r.high[a] = static_cast<float>(box.hi[a] * s - camera_origin[a]);
      }
      const Eigen::Vector3d base = world_to_camera * Eigen::Vector3d(r.low[0], r.low[1], r.low[2]);
      const Eigen::Vector3d edge_x = ex * double{box.hi[0] - box.lo[0]}, edge_y = ey * double{box.hi[1] - box.lo[1]},
                            edge_z = ez * double{box.hi[2] - box.lo[2]};
      double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
      double u_min = z_min, u_max = z_max, v_min = z_min, v_max = z_max;
      bool projectable = true;
      for (int c = 0; c < 8; ++c) {
        Eigen::Vector3d p = base;
        if (c & 1) p += edge_x;
        if (c & 2) p += edge_y;
        if (c & 4) p += edge_z;
        z_min = std::min(z_min, p.z());
        z_max = std::max(z_max, p.z());
        if (p.z() < kMinProjectableDepth) {
          projectable = false;
          continue;
        }
        const double inv_z = 1.0 / p.z();
        const double u = k.fx * p.x() * inv_z + k.cx, v = k.fy * p.y() * inv_z + k.cy;
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
        v_min = std::min(v_min, v);
        v_max = std::max(v_max, v);
      }
      if (z_max < min_depth || z_min > max_depth) continue;  // outside the depth range entirely
      if (!projectable) {
        const auto far = static_cast<float>(std::min(z_max, max_depth) + far_margin);
        out.behind_camera_far = std::max(out.behind_camera_far, far);
        continue;
      }
      // Pixel centres (integers) inside [u_min, u_max] x [v_min, v_max], clipped to the image.
      const double u0 = std::max(std::ceil(u_min), 0.0), u1 = std::min(std::floor(u_max), k.width - 1.0);
      const double v0 = std::max(std::ceil(v_min), 0.0), v1 = std::min(std::floor(v_max), k.height - 1.0);
      if (u0 > u1 || v0 > v1) continue;
      // The half-space along the ray: t a(u, v) <= c, a linear in the pixel.
      const Eigen::Vector3d g = Eigen::Vector3d(box.normal[0], box.normal[1], box.normal[2]) / s;
      r.plane_du = static_cast<float>(g.dot(ray_du));
      r.plane_dv = static_cast<float>(g.dot(ray_dv));
      r.plane_at_origin = static_cast<float>(g.dot(ray_at_origin));
      r.plane_c = static_cast<float>(double{box.offset} - g.dot(camera_origin));
      r.u0 = static_cast<int>(u0);
      r.u1 = static_cast<int>(u1);
      r.v0 = static_cast<int>(v0);
      r.v1 = static_cast<int>(v1);
      out.rects.push_back(r);
    }
  });

  // A box behind the camera plane opens every pixel from the near clip to its far depth. The
  // others are filed under every band of rows their rectangle touches (a counting sort).
  open_far_ = -kInf;
  band_start_.assign(static_cast<std::size_t>(bandCount()) + 1, 0);
  for (const Footprints& f : per_thread) {
    open_far_ = std::max(open_far_, f.behind_camera_far);
    for (const Rect& r : f.rects)
      for (int band = r.v0 / kBandRows; band <= r.v1 / kBandRows; ++band) ++band_start_[band + 1];
  }
  open_near_ = open_far_ > -kInf ? static_cast<float>(min_depth - near_margin) : kInf;
  near_margin_ = static_cast<float>(near_margin);
  far_margin_ = static_cast<float>(far_margin);

  for (std::size_t band = 0; band + 1 < band_start_.size(); ++band) band_start_[band + 1] += band_start_[band];
  footprints_.resize(band_start_.back());
  std::vector<std::size_t> next(band_start_.begin(), band_start_.end() - 1);
  for (const Footprints& f : per_thread)
    for (const Rect& r : f.rects)
      for (int band = r.v0 / kBandRows; band <= r.v1 / kBandRows; ++band) footprints_[next[band]++] = r;
}

void SurfaceDepthBounds::rasterizeBand(int band, BandBounds& out) const {
  out.v_begin_ = band * kBandRows;
  out.width_ = width_;
  const int rows = std::min(kBandRows, height_ - out.v_begin_);
  const std::size_t pixels = static_cast<std::size_t>(rows) * width_;
  out.near_.assign(pixels + kBandPadding, open_near_);
  out.far_.assign(pixels + kBandPadding, open_far_);
  out.inverse_direction_.resize(3 * pixels + kBandPadding);
  const BandView view{
      out.v_begin_, rows,       width_, out.near_.data(), out.far_.data(), out.inverse_direction_.data(),
      near_margin_, far_margin_};
  const Rect* first = footprints_.data() + band_start_[band];
  const Rect* last = footprints_.data() + band_start_[band + 1];
  if (raycastKernel() == RaycastKernel::kAvx2) {
    fillInverseDirectionsAvx2(view, ray_du_, ray_dv_, ray_at_origin_);
    clipRectsAvx2(view, first, last);
  } else {
    fillInverseDirections(view, ray_du_, ray_dv_, ray_at_origin_);
    clipRects(view, first, last);
  }
}

// Per pixel and world axis, the inverse of the ray's direction component (depth per metre along
// that axis), kept finite: a ray parallel to an axis gets a huge value of either sign, which puts
// a box's slab on that axis either around all depths or beyond any. (Float: the slab depths need
// no more than the margins allow, and the loop vectorises.)
void fillInverseDirections(const SurfaceDepthBounds::BandView& band, const double ray_du[3], const double ray_dv[3],
                           const double ray_at_origin[3]) {
  const std::size_t pixels = band.pixels();
  for (int a = 0; a < 3; ++a)
    for (int v = band.v_begin; v < band.v_begin + band.rows; ++v) {
      float* row = band.inverse_direction + a * pixels + static_cast<std::size_t>(v - band.v_begin) * band.width;
      const auto du = static_cast<float>(ray_du[a]), at_u0 = static_cast<float>(ray_dv[a] * v + ray_at_origin[a]);
      for (int u = 0; u < band.width; ++u)
        row[u] = std::clamp(1.0f / (du * static_cast<float>(u) + at_u0), -kHugeInverse, kHugeInverse);
    }
}

void clipRects(const SurfaceDepthBounds::BandView& band, const SurfaceDepthBounds::Rect* first,
               const SurfaceDepthBounds::Rect* last) {
  const std::size_t pixels = band.pixels();
  const float near_margin = band.near_margin, far_margin = band.far_margin;
  for (const SurfaceDepthBounds::Rect* rect = first; rect != last; ++rect) {
    const SurfaceDepthBounds::Rect& f = *rect;
    // Locals, so that the compiler can keep them in registers across the stores into the rows
    // (and vectorise the loop over u).
    const float lx = f.low[0], hx = f.high[0], ly = f.low[1], hy = f.high[1], lz = f.low[2], hz = f.high[2];
    const float plane_du = f.plane_du, plane_c = f.plane_c;
    const int v0 = std::max(f.v0, band.v_begin), v1 = std::min(f.v1, band.v_begin + band.rows - 1);
    for (int v = v0; v <= v1; ++v) {
      const std::size_t row_start = static_cast<std::size_t>(v - band.v_begin) * band.width;
      float* __restrict near_row = band.near + row_start;
      float* __restrict far_row = band.far + row_start;
      const float* __restrict inv_x = band.inverse_direction + row_start;
      const float* __restrict inv_y = inv_x + pixels;
      const float* __restrict inv_z = inv_y + pixels;
      const float plane_row = f.plane_dv * static_cast<float>(v) + f.plane_at_origin;
      for (int u = f.u0; u <= f.u1; ++u) {
        // The ray's depths inside the box: the overlap of its three slabs.
        const float x0 = lx * inv_x[u], x1 = hx * inv_x[u];
        const float y0 = ly * inv_y[u], y1 = hy * inv_y[u];
        const float z0 = lz * inv_z[u], z1 = hz * inv_z[u];
        // And the half-space: t a <= c, entered at c / a where a < 0, left there where a > 0.
        const float a = plane_du * static_cast<float>(u) + plane_row;
        const float a_safe = std::copysign(std::max(std::abs(a), kTinySlope), a);
        const float t_plane = plane_c / a_safe;
        // (a < 0: beyond = +huge, so the plane bounds the entry only; a > 0: the exit only.)
        const float beyond = std::copysign(kBeyondAnyDepth, -a_safe);
        const float plane_enter = std::min(t_plane, beyond);
        const float plane_leave = std::max(t_plane, beyond);
        const float enter =
            std::max(std::max(std::max(std::min(x0, x1), std::min(y0, y1)), std::min(z0, z1)), plane_enter);
        const float leave =
            std::min(std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::max(z0, z1)), plane_leave);
        // A ray that misses the box gets a near bound far beyond and a far bound far before any
        // depth (arithmetic rather than a branch, so that the loop vectorises).
        const float missed = static_cast<float>(enter > leave) * kBeyondAnyDepth;
        near_row[u] = std::min(near_row[u], enter - near_margin + missed);
        far_row[u] = std::max(far_row[u], leave + far_margin - missed);
      }
    }
  }
}

}  // namespace semfuse::render::detail
