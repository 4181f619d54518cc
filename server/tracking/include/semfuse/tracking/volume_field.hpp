#pragma once
// The labeled OpenVDB volume as the tracker's SdfField: trilinear TSDF and its gradient through
// LeafCacheSampler (false wherever any of the 8 surrounding voxels is unobserved, which is exactly
// the "weight > 0" rule of the tracker). A sampler keeps the leaves it has read for as long as it
// lives: one alignment, over which the points come back to the same leaves pass after pass.
#include <memory>

#include "semfuse/tracking/sdf_field.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::tracking {

class VolumeField final : public SdfField {
 public:
  // The volume must outlive this object and must not change while an alignment runs.
  explicit VolumeField(const volume::LabeledVolume& volume) : volume_(&volume) {}

  float truncation() const override { return static_cast<float>(volume_->params().truncation); }
  std::unique_ptr<SdfSampler> makeSampler() const override;

 private:
  const volume::LabeledVolume* volume_;
};

}  // namespace semfuse::tracking
