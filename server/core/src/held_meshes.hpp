#pragma once
// The meshes clients are fetching in chunks (mesh service): each PLY is kept under an id until
// a few newer ones replace it, so that concurrent clients can page through their own.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace semfuse::server {

class HeldMeshes {
 public:
  explicit HeldMeshes(std::size_t kept = 4) : kept_(kept) {}

  // Keeps `ply` and returns its id (1, 2, ...); the oldest beyond the kept number are dropped.
  uint64_t hold(std::shared_ptr<const std::string> ply);
  // The mesh with that id, or null when it is not held (any more).
  std::shared_ptr<const std::string> find(uint64_t id) const;

 private:
  const std::size_t kept_;
  mutable std::mutex mutex_;
  std::map<uint64_t, std::shared_ptr<const std::string>> meshes_;  // oldest first
  uint64_t next_id_ = 1;
};

}  // namespace semfuse::server
