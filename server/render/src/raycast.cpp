#include "semfuse/render/raycast.hpp"

#include "semfuse/core/pose_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "ray_marcher.hpp"
#include "surface_depth_bounds.hpp"
#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::render {
namespace {

using detail::MarchRay;
using detail::RayMarcher;

Status validate(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& camera_to_world,
                const RaycastOptions& options) {
  if (k.width <= 0 || k.height <= 0)
    return makeError("raycast image size must be positive, got " + std::to_string(k.width) + "x" +
                     std::to_string(k.height));
  if (!(k.fx > 0.0 && k.fy > 0.0 && std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) &&
        std::isfinite(k.cy)))
    return makeError("raycast intrinsics must have finite, positive focal lengths and a finite principal point");
  if (Status pose = checkRigidPose(camera_to_world); !pose) return makeError("raycast " + pose.error());
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
RaycastImages allocateImages(const PinholeIntrinsics& k, RenderLayers layers) {
  RaycastImages images;
  if (layers & kDepthLayer) images.depth.create(k.height, k.width, CV_32FC1);
  if (layers & kNormalLayer) images.normals.create(k.height, k.width, CV_32FC3);
  if (layers & kLabelLayer) images.labels.create(k.height, k.width, CV_16UC1);
  if (layers & kScoreLayer) images.scores.create(k.height, k.width, CV_32FC1);
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
void shadePixel(volume::VolumeSampler& sampler, const MarchRay& ray, double t, RenderLayers layers,
                RaycastImages& images, int u, int v) {
  const Eigen::Vector3f point = (ray.origin + t * ray.direction).cast<float>();
  if (layers & kDepthLayer) images.depth.at<float>(v, u) = static_cast<float>(t);
  if (layers & kNormalLayer) {
    float f;
    Eigen::Vector3f gradient;
    if (sampler.tsdfAndGradient(point, f, gradient) && gradient.squaredNorm() > 0.0f) {
      const Eigen::Vector3f n = gradient.normalized();
      images.normals.at<cv::Vec3f>(v, u) = cv::Vec3f(n.x(), n.y(), n.z());
    }
  }
  if (layers & (kLabelLayer | kScoreLayer)) {
    volume::VoxelValue voxel;
    if (sampler.nearestVoxel(point, voxel)) {
      if (layers & kLabelLayer) images.labels.at<uint16_t>(v, u) = voxel.label;
      if (layers & kScoreLayer) images.scores.at<float>(v, u) = voxel.score;
    }
  }
  if (layers & kColorLayer) {
    volume::Rgb8 rgb;
    if (sampler.nearestColor(point, rgb)) images.color.at<cv::Vec3b>(v, u) = cv::Vec3b(rgb.r, rgb.g, rgb.b);
  }
}

}  // namespace

Result<RaycastImages> raycast(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                              const Pose& camera_to_world, const RaycastOptions& options) {
  if (Status valid = validate(volume, k, camera_to_world, options); !valid) return makeError(valid.error());
  RaycastImages images = allocateImages(k, options.layers);
  const WorldBox bounds = allocatedBounds(volume);
  if (bounds.empty) {
    for (int v = 0; v < k.height; ++v) clearRow(images, v);
    return images;
  }

  const Eigen::Matrix3d rotation = camera_to_world.linear();
  const Eigen::Vector3d origin = camera_to_world.translation();
  auto marchRow = [&](int v, RayMarcher& marcher, volume::VolumeSampler& sampler, const detail::BandBounds* band) {
    clearRow(images, v);
    for (int u = 0; u < k.width; ++u) {
      MarchRay ray{origin, rotation * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0), options.min_depth,
                   options.max_depth};
      if (band) {
        double near, far;
        if (!band->depthRange(u, v, near, far)) continue;
        ray.t_min = std::max(ray.t_min, near);
        ray.t_max = std::min(ray.t_max, far);
      }
      double t;
      if (clipToBox(bounds, ray) && marcher.findSurface(ray, t))
        shadePixel(sampler, ray, t, options.layers, images, u, v);
    }
  };
  if (!options.skip_empty_space) {
    // The baseline clips each ray to the allocated box and marches all of it.
    tbb::parallel_for(tbb::blocked_range<int>(0, k.height, 4), [&](const tbb::blocked_range<int>& rows) {
      RayMarcher marcher(volume, false);
      volume::VolumeSampler sampler(volume);
      for (int v = rows.begin(); v < rows.end(); ++v) marchRow(v, marcher, sampler, nullptr);
    });
    return images;
  }
  // Each ray marches only between the nearest and farthest block with a surface voxel over its
  // pixel. Bands of rows in small tasks: rays through empty space cost far less than rays through
  // the band, so fine-grained tasks balance the two cores.
  const detail::SurfaceDepthBounds surface_bounds(volume, k, camera_to_world, options.min_depth, options.max_depth);
  tbb::parallel_for(tbb::blocked_range<int>(0, surface_bounds.bandCount(), 1), [&](const tbb::blocked_range<int>& bands) {
    RayMarcher marcher(volume, true);
    volume::VolumeSampler sampler(volume);
    detail::BandBounds band_bounds;
    for (int band = bands.begin(); band < bands.end(); ++band) {
      surface_bounds.rasterizeBand(band, band_bounds);
      const int v_end = std::min(k.height, (band + 1) * detail::SurfaceDepthBounds::kBandRows);
      for (int v = band * detail::SurfaceDepthBounds::kBandRows; v < v_end; ++v)
        marchRow(v, marcher, sampler, &band_bounds);
    }
  });
  return images;
}

}  // namespace semfuse::render
