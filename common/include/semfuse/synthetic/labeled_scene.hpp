#pragma once
// A scene of labeled, coloured analytic solids. It answers the two questions tests need the
// truth for: what does a ray hit (depth, normal, label, colour), and what is the nearest surface
// to a point (signed distance, label).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/synthetic/primitives.hpp"

namespace semfuse::synthetic {

using Rgb = std::array<uint8_t, 3>;

// Procedural surface pattern, evaluated at the world point so that it is consistent across views
// (a colour image must not be flat for colour fusion and photometric tests to mean anything).
enum class Texture { kChecker, kStripes, kNoise };

struct SceneObject {
  std::string name;
  Shape shape;
  LabelId label = kUnlabeled;
  Rgb color{128, 128, 128};
  Texture texture = Texture::kNoise;
};

struct SurfaceHit {
  double t = 0.0;          // ray parameter (camera depth for a camera ray, see Ray)
  Eigen::Vector3d point;   // world
  Eigen::Vector3d normal;  // world, unit, outward from the solid
  std::size_t object = 0;  // index into LabeledScene::objects()
};

struct NearestSurface {
  double signed_distance = 0.0;  // negative inside a solid
  LabelId label = kUnlabeled;
  std::size_t object = 0;
};

class LabeledScene {
 public:
  // texture_seed varies the noise textures only; geometry and labels never depend on it.
  explicit LabeledScene(uint64_t texture_seed = 0) : texture_seed_(texture_seed) {}

  std::size_t add(SceneObject object);
  const std::vector<SceneObject>& objects() const { return objects_; }

  // Nearest entry into any solid with t > t_min.
  std::optional<SurfaceHit> castRay(const Ray& ray, double t_min = 0.0) const;

  // Distance field of the union of the solids: min over objects, label of the closest one.
  // Exact outside all solids (where a fused TSDF is observed); requires at least one object.
  NearestSurface nearestSurface(const Eigen::Vector3d& point) const;

  // Textured colour of the surface at a hit.
  Rgb colorAt(const SurfaceHit& hit) const;

 private:
  std::vector<SceneObject> objects_;
  std::vector<Aabb> bounds_;
  uint64_t texture_seed_;
};

}  // namespace semfuse::synthetic
