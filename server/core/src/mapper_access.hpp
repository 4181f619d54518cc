#pragma once
// The server's map, as the query handlers read it: Mapper::read under its shared lock, and its
// snapshots.
#include "map_access.hpp"
#include "mapper.hpp"

namespace semfuse::server {

class MapperAccess final : public MapAccess {
 public:
  explicit MapperAccess(const Mapper& mapper) : mapper_(mapper) {}
  void read(const std::function<void(const volume::LabeledVolume&)>& fn) const override {
    mapper_.read([&](const volume::LabeledVolume& volume) { fn(volume); });
  }
  std::shared_ptr<const volume::LabeledVolume> snapshot() const override { return mapper_.snapshot(); }
  const LabelLegend& legend() const override { return mapper_.legend(); }

 private:
  const Mapper& mapper_;
};

}  // namespace semfuse::server
