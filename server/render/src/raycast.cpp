#include "semfuse/render/raycast.hpp"

#include "semfuse/core/camera_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cell_marcher.hpp"
#include "crossing_cells.hpp"
#include "ray_marcher.hpp"
#include "semfuse/volume/cell_interpolation.hpp"
#include "semfuse/volume/volume_sampler.hpp"
#include "surface_depth_bounds.hpp"

namespace semfuse::render {
namespace {

using detail::CellMarcher;
using detail::MarchRay;
using detail::RayMarcher;
using detail::SurfaceHit;

Status validate(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& camera_to_world,
                const RaycastOptions& options) {
  if (Status camera = checkCamera(k, camera_to_world); !camera) return camera.errorInfo().prefixed("raycast ");
  if (!(options.min_depth >= 0.0 && options.max_depth > options.min_depth && std::isfinite(options.max_depth)))
    return makeError("raycast depth range must satisfy 0 <= min_depth < max_depth < inf");
  if ((options.layers & kAllLayers) == 0 || (options.layers & ~static_cast<uint32_t>(kAllLayers)) != 0)
    return makeError("raycast layer mask " + std::to_string(options.layers) + " names no or unknown layers");
  if ((options.layers & kColorLayer) && !volume.hasColor())
    return makeError("raycast colour layer requested but the volume keeps no colour");
  return Status::Ok();
}

// World box that holds every voxel a trilinear sample could read: the leaves' bounds, widened by
// the half voxel around each centre and the +1 corner.
struct WorldBox {
  Eigen::Vector3d min, max;
  bool empty = true;
};

WorldBox allocatedBounds(const volume::LabeledVolume& volume) {
  openvdb::CoordBBox bbox;
  WorldBox box;
  if (!volume.geometryGrid().tree().evalLeafBoundingBox(bbox)) return box;
  const double s = volume.voxelSize();
  box.min = Eigen::Vector3d(bbox.min().x(), bbox.min().y(), bbox.min().z()) * s - Eigen::Vector3d::Constant(s);
  box.max = Eigen::Vector3d(bbox.max().x(), bbox.max().y(), bbox.max().z()) * s + Eigen::Vector3d::Constant(s);
  box.empty = false;
  return box;
}

// Narrows [t_min, t_max) to the part of the ray inside the box; false when it misses.
bool clipToBox(const WorldBox& box, MarchRay& ray) {
  for (int axis = 0; axis < 3; ++axis) {
    const double d = ray.direction[axis], o = ray.origin[axis];
    if (d == 0.0) {
      if (o < box.min[axis] || o > box.max[axis]) return false;
      continue;
    }
    double t0 = (box.min[axis] - o) / d, t1 = (box.max[axis] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    ray.t_min = std::max(ray.t_min, t0);
    ray.t_max = std::min(ray.t_max, t1);
  }
  return ray.t_min < ray.t_max;
}

// The images, uninitialised: the threads that march the rows clear them (clearRow), so the
// pages are first touched in parallel and are in cache when the hits are written.
RaycastImages allocateImages(const PinholeIntrinsics& k, RaycastLayers layers) {
  RaycastImages images;
  if (layers & kDepthLayer) images.depth.create(k.height, k.width, CV_32FC1);
  if (layers & kNormalsLayer) images.normals.create(k.height, k.width, CV_32FC3);
  if (layers & kLabelsLayer) images.labels.create(k.height, k.width, CV_16UC1);
  if (layers & kConfidenceLayer) images.scores.create(k.height, k.width, CV_32FC1);
  if (layers & kColorLayer) images.color.create(k.height, k.width, CV_8UC3);
  return images;
}

// Zero (no surface) in row v of every requested image.
void clearRow(RaycastImages& images, int v) {
  for (cv::Mat* image : {&images.depth, &images.normals, &images.labels, &images.scores, &images.color})
    if (!image->empty()) std::memset(image->ptr(v), 0, image->cols * image->elemSize());
}

// Writes the requested layers of one pixel whose ray meets the surface at t.
// Normals from the gradient and the nearest voxel's layers are read once per hit, not per sample.
void shadePixel(volume::VolumeSampler& sampler, const MarchRay& ray, double t, RaycastLayers layers,
                RaycastImages& images, int u, int v) {
  const Eigen::Vector3f point = (ray.origin + t * ray.direction).cast<float>();
  if (layers & kDepthLayer) images.depth.at<float>(v, u) = static_cast<float>(t);
  if (layers & kNormalsLayer) {
    float f;
    Eigen::Vector3f gradient;
    if (sampler.tsdfAndGradient(point, f, gradient) && gradient.squaredNorm() > 0.0f) {
      const Eigen::Vector3f n = gradient.normalized();
      images.normals.at<cv::Vec3f>(v, u) = cv::Vec3f(n.x(), n.y(), n.z());
    }
  }
  if (layers & (kLabelsLayer | kConfidenceLayer)) {
    volume::VoxelValue voxel;
    if (sampler.nearestVoxel(point, voxel)) {
      if (layers & kLabelsLayer) images.labels.at<uint16_t>(v, u) = voxel.label;
      if (layers & kConfidenceLayer) images.scores.at<float>(v, u) = voxel.score;
    }
  }
  if (layers & kColorLayer) {
    volume::Rgb8 rgb;
    if (sampler.nearestColor(point, rgb)) images.color.at<cv::Vec3b>(v, u) = cv::Vec3b(rgb.r, rgb.g, rgb.b);
  }
}

// The same layers from the cell the fast path found the surface in: the trilinear gradient of
// its corners at the hit, and the label, score and colour of the corner nearest to the hit (read
// from the leaf or upper neighbour that holds it, as the cell's corners were).
void shadeHit(const SurfaceHit& hit, RaycastLayers layers, RaycastImages& images, int u, int v) {
  if (layers & kDepthLayer) images.depth.at<float>(v, u) = static_cast<float>(hit.t);
  const float fx = hit.fraction[0], fy = hit.fraction[1], fz = hit.fraction[2];
  if (layers & kNormalsLayer) {
    Eigen::Vector3f gradient;
    volume::trilinearWithGradient(hit.tsdf, fx, fy, fz, gradient);
    if (gradient.squaredNorm() > 0.0f) {
      const Eigen::Vector3f n = gradient.normalized();
      images.normals.at<cv::Vec3f>(v, u) = cv::Vec3f(n.x(), n.y(), n.z());
    }
  }
  if (!(layers & (kLabelsLayer | kConfidenceLayer | kColorLayer))) return;
  // The nearest corner, leaf-local (0..8 on each axis: 8 is in the upper neighbour).
  const int x = hit.local[0] + (fx >= 0.5f ? 1 : 0), y = hit.local[1] + (fy >= 0.5f ? 1 : 0),
            z = hit.local[2] + (fz >= 0.5f ? 1 : 0);
  const int holder = detail::CrossingCells::LeafCells::upperHolding(x, y, z);
  const int offset = detail::CrossingCells::LeafCells::offsetInLeaf(x, y, z);
  if (layers & (kLabelsLayer | kConfidenceLayer)) {
    const volume::PackedVoxel* voxels = hit.leaf->upper[holder];
    const volume::PackedVoxel voxel = voxels ? voxels[offset] : volume::kUnobservedVoxel;
    if (layers & kLabelsLayer) images.labels.at<uint16_t>(v, u) = volume::unpackLabel(voxel);
    if (layers & kConfidenceLayer) images.scores.at<float>(v, u) = volume::unpackScore(voxel);
  }
  if (layers & kColorLayer) {
    if (const volume::PackedColor* colors = hit.leaf->upper_colors[holder]) {
      const volume::Rgb8 rgb = volume::unpackColor(colors[offset]);
      images.color.at<cv::Vec3b>(v, u) = cv::Vec3b(rgb.r, rgb.g, rgb.b);
    }
  }
}

MarchRay rayThrough(const PinholeIntrinsics& k, const Pose& camera_to_world, const RaycastOptions& options, int u,
                    int v) {
  return MarchRay{camera_to_world.translation(),
                  camera_to_world.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0),
                  options.min_depth, options.max_depth};
}

// The reference: each ray clipped to the allocated box and marched all the way by samples.
RaycastImages renderPlain(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& camera_to_world,
                          const RaycastOptions& options) {
  RaycastImages images = allocateImages(k, options.layers);
  const WorldBox bounds = allocatedBounds(volume);
  tbb::parallel_for(tbb::blocked_range<int>(0, k.height, 4), [&](const tbb::blocked_range<int>& rows) {
    RayMarcher marcher(volume);
    volume::VolumeSampler sampler(volume);
    for (int v = rows.begin(); v < rows.end(); ++v) {
      clearRow(images, v);
      if (bounds.empty) continue;
      for (int u = 0; u < k.width; ++u) {
        MarchRay ray = rayThrough(k, camera_to_world, options, u, v);
        double t;
        if (clipToBox(bounds, ray) && marcher.findSurface(ray, t))
          shadePixel(sampler, ray, t, options.layers, images, u, v);
      }
    }
  });
  return images;
}

// The fast path: each ray walks the cells between the nearest and farthest block of crossing
// cells over its pixel, reading voxels only in crossing cells. Bands of rows in small tasks: rays
// over empty pixels cost nothing, so fine-grained tasks balance the cores.
RaycastImages renderCells(detail::CrossingCells& cells, double voxel_size, const PinholeIntrinsics& k,
                          const Pose& camera_to_world, const RaycastOptions& options) {
  RaycastImages images = allocateImages(k, options.layers);
  cells.findCrossings();
  const detail::SurfaceDepthBounds surface_bounds(cells, voxel_size, k, camera_to_world, options.min_depth,
                                                  options.max_depth);
  tbb::parallel_for(tbb::blocked_range<int>(0, surface_bounds.bandCount(), 1),
                    [&](const tbb::blocked_range<int>& bands) {
                      CellMarcher marcher(cells, voxel_size);
                      detail::BandBounds band_bounds;
                      SurfaceHit hit;
                      for (int band = bands.begin(); band < bands.end(); ++band) {
                        surface_bounds.rasterizeBand(band, band_bounds);
                        const int v_end = std::min(k.height, (band + 1) * detail::SurfaceDepthBounds::kBandRows);
                        for (int v = band * detail::SurfaceDepthBounds::kBandRows; v < v_end; ++v) {
                          clearRow(images, v);
                          for (int u = 0; u < k.width; ++u) {
                            double near, far;
                            if (!band_bounds.depthRange(u, v, near, far)) continue;
                            MarchRay ray = rayThrough(k, camera_to_world, options, u, v);
                            ray.t_min = std::max(ray.t_min, near);
                            ray.t_max = std::min(ray.t_max, far);
                            if (marcher.findSurface(ray, hit)) shadeHit(hit, options.layers, images, u, v);
                          }
                        }
                      }
                    });
  return images;
}

detail::CrossingCells::Options cellOptions(const RaycastOptions& options, bool copy) {
  detail::CrossingCells::Options o;
  o.copy_voxels = copy;
  o.with_color = (options.layers & kColorLayer) != 0;
  return o;
}

}  // namespace

struct PreparedRaycast::State {
  PinholeIntrinsics intrinsics;
  Pose camera_to_world;
  RaycastOptions options;
  double voxel_size = 0.0;
  std::optional<detail::CrossingCells> cells;   // the fast path's copy (masks filled when rendering)
  std::optional<volume::LabeledVolume> volume;  // the plain march's copy
};

Result<RaycastImages> raycast(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                              const Pose& camera_to_world, const RaycastOptions& options) {
  if (Status valid = validate(volume, k, camera_to_world, options); !valid) return makeError(valid.error());
  if (!options.skip_empty_space) return renderPlain(volume, k, camera_to_world, options);
  detail::CrossingCells cells(volume, k, camera_to_world, options.min_depth, options.max_depth,
                              cellOptions(options, false));
  return renderCells(cells, volume.voxelSize(), k, camera_to_world, options);
}

Result<PreparedRaycast> prepareRaycast(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                                       const Pose& camera_to_world, const RaycastOptions& options) {
  if (Status valid = validate(volume, k, camera_to_world, options); !valid) return makeError(valid.error());
  auto state = std::make_shared<PreparedRaycast::State>();
  state->intrinsics = k;
  state->camera_to_world = camera_to_world;
  state->options = options;
  state->voxel_size = volume.voxelSize();
  if (options.skip_empty_space)
    state->cells.emplace(volume, k, camera_to_world, options.min_depth, options.max_depth, cellOptions(options, true));
  else state->volume.emplace(volume.deepCopy());
  PreparedRaycast prepared;
  prepared.state_ = std::move(state);
  return prepared;
}

Result<RaycastImages> raycast(PreparedRaycast&& prepared) {
  const std::shared_ptr<PreparedRaycast::State> state = std::move(prepared.state_);
  if (!state) return makeError("raycast of an empty or already rendered PreparedRaycast (use prepareRaycast)");
  if (state->volume) return renderPlain(*state->volume, state->intrinsics, state->camera_to_world, state->options);
  return renderCells(*state->cells, state->voxel_size, state->intrinsics, state->camera_to_world, state->options);
}

}  // namespace semfuse::render
