#pragma once
// Test fixture: the exact signed distance of a synthetic scene, truncated like a TSDF, as an
// SdfField. Isolates the tracker's mathematics from the volume's discretisation: with the exact
// field, an alignment must reach the true pose to numerical precision.
#include <algorithm>
#include <memory>

#include <Eigen/Geometry>

#include "semfuse/synthetic/labeled_scene.hpp"
#include "semfuse/tracking/sdf_field.hpp"

namespace semfuse::tracking::testing {

class AnalyticField final : public SdfField {
 public:
  // Only points inside `observed` can be observed: a camera inside the room never sees behind
  // its walls, where the exact distance would otherwise attract points to the walls' far faces.
  AnalyticField(const synthetic::LabeledScene& scene, float truncation,
                Eigen::AlignedBox3d observed = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1e3),
                                                                   Eigen::Vector3d::Constant(1e3)))
      : scene_(&scene), truncation_(truncation), observed_(observed) {}

  float truncation() const override { return truncation_; }

  std::unique_ptr<SdfSampler> makeSampler() const override {
    return std::make_unique<Sampler>(*scene_, truncation_, observed_);
  }

 private:
  class Sampler final : public SdfSampler {
   public:
    Sampler(const synthetic::LabeledScene& scene, float truncation, const Eigen::AlignedBox3d& observed)
        : scene_(&scene), truncation_(truncation), observed_(observed) {}

    bool sample(const Eigen::Vector3f& p, SdfSample& out) override {
      const Eigen::Vector3d x = p.cast<double>();
      if (!observed_.contains(x)) return false;
      const double d = distance(x);
      // As in a fused TSDF: deep inside a solid nothing was ever observed; in free space beyond
      // the band the value saturates at +truncation.
      if (d < -truncation_) return false;
      out.distance = static_cast<float>(std::min<double>(d, truncation_));
      const double h = 1e-5;
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d step = Eigen::Vector3d::Zero();
        step[a] = h;
        out.gradient[a] =
            d >= truncation_ ? 0.0f : static_cast<float>((distance(x + step) - distance(x - step)) / (2 * h));
      }
      return true;
    }

   private:
    double distance(const Eigen::Vector3d& x) const { return scene_->nearestSurface(x).signed_distance; }
    const synthetic::LabeledScene* scene_;
    float truncation_;
    Eigen::AlignedBox3d observed_;
  };

  const synthetic::LabeledScene* scene_;
  float truncation_;
  Eigen::AlignedBox3d observed_;
};

}  // namespace semfuse::tracking::testing
