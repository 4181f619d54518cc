#include "semfuse/synthetic/labeled_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hash_noise.hpp"

namespace semfuse::synthetic {
namespace {

// Slab test against an axis-aligned box: can the ray reach it closer than t_best? inv_direction
// is 1 / direction per axis (+-inf for 0 is what the slab test wants), computed once per ray.
bool mayHit(const Aabb& box, const Ray& ray, const Eigen::Vector3d& inv_direction, double t_min, double t_best) {
  double t0 = t_min, t1 = t_best;
  for (int axis = 0; axis < 3; ++axis) {
    const double inv = inv_direction[axis];
    double a = (box.min[axis] - ray.origin[axis]) * inv;
    double b = (box.max[axis] - ray.origin[axis]) * inv;
    if (a > b) std::swap(a, b);
    if (std::isnan(a) || std::isnan(b)) continue;  // origin on a slab plane with d = 0
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

uint8_t shade(uint8_t base, double factor) { return static_cast<uint8_t>(std::clamp(base * factor, 0.0, 255.0)); }

}  // namespace

std::size_t LabeledScene::add(SceneObject object) {
  if (object.instance == 0) object.instance = next_instance_;
  next_instance_ = std::max(next_instance_, object.instance + 1);
  bounds_.push_back(bounds(object.shape));
  objects_.push_back(std::move(object));
  return objects_.size() - 1;
}

std::optional<SurfaceHit> LabeledScene::castRay(const Ray& ray, double t_min) const {
  std::optional<SurfaceHit> best;
  double t_best = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d inv_direction = ray.direction.cwiseInverse();
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (!mayHit(bounds_[i], ray, inv_direction, t_min, t_best)) continue;
    if (auto hit = intersect(objects_[i].shape, ray, t_min); hit && hit->t < t_best) {
      t_best = hit->t;
      best = SurfaceHit{hit->t, ray.origin + hit->t * ray.direction, hit->normal, i};
    }
  }
  return best;
}

NearestSurface LabeledScene::nearestSurface(const Eigen::Vector3d& point) const {
  NearestSurface nearest{std::numeric_limits<double>::infinity(), kUnlabeled, 0};
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const double d = signedDistance(objects_[i].shape, point);
    if (d < nearest.signed_distance) nearest = {d, objects_[i].label, i};
  }
  return nearest;
}

Rgb LabeledScene::colorAt(const SurfaceHit& hit) const {
  const SceneObject& object = objects_[hit.object];
  const Eigen::Vector3d& p = hit.point;
  // Pattern in [-1, 1], mapped to a brightness factor around 1 so the hue stays recognisable.
  double pattern = 0.0;
  switch (object.texture) {
    case Texture::kChecker: {
      constexpr double kTile = 0.5;
      // Offset by half a tile from the surface so that faces lying on tile borders are not
      // ambiguous; the parity of the 3D cell is a 2D checkerboard on any axis-aligned face.
      const Eigen::Vector3d q = (p - 1e-3 * hit.normal) / kTile;
      const long parity = static_cast<long>(std::floor(q.x()) + std::floor(q.y()) + std::floor(q.z()));
      pattern = (parity & 1) ? 0.6 : -0.6;
      pattern += 0.4 * valueNoise(p * 20.0, texture_seed_);
      break;
    }
    case Texture::kStripes:
      pattern =
          0.7 * std::sin(2.0 * M_PI * (p.x() + p.y() + 0.5 * p.z()) / 0.15) + 0.3 * valueNoise(p * 10.0, texture_seed_);
      break;
    case Texture::kNoise:
      pattern = 0.6 * valueNoise(p * 8.0, texture_seed_) + 0.4 * valueNoise(p * 32.0, texture_seed_ + 1);
      break;
  }
  const double factor = 1.0 + 0.35 * pattern;
  return {shade(object.color[0], factor), shade(object.color[1], factor), shade(object.color[2], factor)};
}

}  // namespace semfuse::synthetic
