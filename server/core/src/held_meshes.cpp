#include "held_meshes.hpp"

#include <utility>

namespace semfuse::server {

uint64_t HeldMeshes::hold(std::shared_ptr<const std::string> ply) {
  std::lock_guard lock(mutex_);
  const uint64_t id = next_id_++;
  meshes_[id] = std::move(ply);
  while (meshes_.size() > kept_) meshes_.erase(meshes_.begin());
  return id;
}

std::shared_ptr<const std::string> HeldMeshes::find(uint64_t id) const {
  std::lock_guard lock(mutex_);
  auto it = meshes_.find(id);
  return it == meshes_.end() ? nullptr : it->second;
}

}  // namespace semfuse::server
