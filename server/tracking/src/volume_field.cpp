#include "semfuse/tracking/volume_field.hpp"

#include "semfuse/volume/leaf_cache_sampler.hpp"

namespace semfuse::tracking {

namespace {
class VolumeFieldSampler final : public SdfSampler {
 public:
  explicit VolumeFieldSampler(const volume::LabeledVolume& volume) : sampler_(volume) {}
  bool sample(const Eigen::Vector3f& world_point, SdfSample& out) override {
    return sampler_.tsdfAndGradient(world_point, out.distance, out.gradient);
  }
  bool sampleWithIntensity(const Eigen::Vector3f& world_point, SdfSample& out) override {
    return sampler_.tsdfAndIntensity(world_point, out.distance, out.gradient, out.intensity, out.intensity_gradient,
                                     out.has_intensity);
  }

 private:
  volume::LeafCacheSampler sampler_;
};
}  // namespace

std::unique_ptr<SdfSampler> VolumeField::makeSampler() const { return std::make_unique<VolumeFieldSampler>(*volume_); }

}  // namespace semfuse::tracking
