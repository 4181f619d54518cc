#pragma once
// MapAccess: the map as the query handlers (service_handlers.hpp) see it, read-only and without
// DDS. The server's comes from its Mapper (mapper_access.hpp: the shared lock, cached snapshots);
// VolumeAccess hands a fixed volume to tests and the fuzzer.
#include <functional>
#include <memory>
#include <utility>

#include "semfuse/core/legend.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::server {

class MapAccess {
 public:
  virtual ~MapAccess() = default;
  // Runs fn(volume) under the lock that holds off the fusion thread: for short reads.
  virtual void read(const std::function<void(const volume::LabeledVolume&)>& fn) const = 0;
  // A read-only copy of the map as of the latest write, for long queries that hold no lock.
  virtual std::shared_ptr<const volume::LabeledVolume> snapshot() const = 0;
  virtual const LabelLegend& legend() const = 0;
};

// A map that does not change.
class VolumeAccess final : public MapAccess {
 public:
  VolumeAccess(std::shared_ptr<const volume::LabeledVolume> volume, LabelLegend legend)
      : volume_(std::move(volume)), legend_(std::move(legend)) {}
  void read(const std::function<void(const volume::LabeledVolume&)>& fn) const override { fn(*volume_); }
  std::shared_ptr<const volume::LabeledVolume> snapshot() const override { return volume_; }
  const LabelLegend& legend() const override { return legend_; }

 private:
  std::shared_ptr<const volume::LabeledVolume> volume_;
  LabelLegend legend_;
};

}  // namespace semfuse::server
