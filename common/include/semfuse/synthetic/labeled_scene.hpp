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
  // The object this solid is part of, as a person would point at it: a table's top and legs
  // share one instance. 0 = a new instance of its own (add() numbers it).
  uint32_t instance = 0;
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

  // Returns the solid's index in objects(); an instance of 0 becomes the next unused instance id.
  std::size_t add(SceneObject object);
  // The instance of objects()[index] (>= 1).
  uint32_t instanceOf(std::size_t index) const { return objects_[index].instance; }
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
  uint32_t next_instance_ = 1;
};

}  // namespace semfuse::synthetic
