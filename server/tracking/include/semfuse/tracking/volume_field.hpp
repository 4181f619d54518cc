#pragma once
// The labeled OpenVDB volume as the tracker's SdfField: trilinear TSDF and its gradient through
// VolumeSampler (false wherever any of the 8 surrounding voxels is unobserved, which is exactly
// the "weight > 0" rule of the tracker).
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
