#pragma once
// DistanceSource: the distance field as the distance handlers (distance_handlers.hpp) read it:
// the server's DistanceField (distance_field.hpp), or a field that does not change for tests and
// the fuzzer (FixedDistanceField).
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/esdf/esdf_map.hpp"
#include "semfuse/esdf/semantic_distance.hpp"

namespace semfuse::server {

class DistanceSource {
 public:
  virtual ~DistanceSource() = default;
  // Runs fn(field) under the lock that holds off the field's updates.
  virtual void read(const std::function<void(const esdf::EsdfMap&)>& fn) const = 0;
  // The surface points of `labels` in a KD-tree.
  virtual std::shared_ptr<const esdf::SurfaceIndex> surfaceIndex(std::vector<LabelId> labels) const = 0;
};

// A field that does not change.
class FixedDistanceField final : public DistanceSource {
 public:
  explicit FixedDistanceField(std::shared_ptr<const esdf::EsdfMap> field) : field_(std::move(field)) {}
  void read(const std::function<void(const esdf::EsdfMap&)>& fn) const override { fn(*field_); }
  std::shared_ptr<const esdf::SurfaceIndex> surfaceIndex(std::vector<LabelId> labels) const override {
    return std::make_shared<const esdf::SurfaceIndex>(field_->surfaces().gather(labels));
  }

 private:
  std::shared_ptr<const esdf::EsdfMap> field_;
};

}  // namespace semfuse::server
