#pragma once
// The signed distance field the tracker aligns depth to, seen through a minimal interface so that
// the alignment does not depend on how the field is stored: the labeled OpenVDB volume in the
// server (volume_field.hpp), an analytic field in tests.
#include <memory>

#include <Eigen/Core>

namespace semfuse::tracking {

// Truncated signed distance at a world point (metres, positive in front of the surface) and its
// spatial gradient; with sampleWithIntensity(), also the fused surface colour's intensity (0..1)
// and its gradient, where the field keeps colour.
struct SdfSample {
  float distance = 0.0f;
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
  bool has_intensity = false;
  float intensity = 0.0f;
  Eigen::Vector3f intensity_gradient = Eigen::Vector3f::Zero();
};

// Reads the field. Not thread-safe: each thread uses its own sampler (a sampler may cache tree
// nodes of the field, as OpenVDB accessors do).
class SdfSampler {
 public:
  virtual ~SdfSampler() = default;
  // False where the field was never observed (no weight): such points carry no information and
  // the tracker ignores them.
  virtual bool sample(const Eigen::Vector3f& world_point, SdfSample& out) = 0;
  // The same, plus the intensity where the field has colour (out.has_intensity).
  virtual bool sampleWithIntensity(const Eigen::Vector3f& world_point, SdfSample& out) {
    out.has_intensity = false;
    return sample(world_point, out);
  }
};

class SdfField {
 public:
  virtual ~SdfField() = default;
  // Truncation distance of the TSDF (metres): |distance| never exceeds it, and the robust
  // weights and inlier thresholds of the tracker scale with it.
  virtual float truncation() const = 0;
  // A fresh sampler, valid while the field is not modified (the tracker makes new ones for every
  // frame, since integration changes the field between frames).
  virtual std::unique_ptr<SdfSampler> makeSampler() const = 0;

  // The field does not change between these two calls (the server's map lock; nothing to do for a
  // field that never changes). The tracker reads the field only inside them, one reading per
  // alignment, so that what needs no field (pyramids, image alignment, keypoints) leaves it free.
  virtual void beginReading() const {}
  virtual void endReading() const {}
};

// One reading of a field, for as long as it lives.
class FieldReading {
 public:
  explicit FieldReading(const SdfField& field) : field_(field) { field_.beginReading(); }
  ~FieldReading() { field_.endReading(); }
  FieldReading(const FieldReading&) = delete;
  FieldReading& operator=(const FieldReading&) = delete;

 private:
  const SdfField& field_;
};

}  // namespace semfuse::tracking
