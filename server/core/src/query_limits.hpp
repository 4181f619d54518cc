#pragma once
// The server's bounds on what one query may ask (--max-raycast-pixels, --mesh-chunk-bytes); the
// defaults are here only.
#include <cstddef>
#include <cstdint>

namespace semfuse::server {

struct QueryLimits {
  uint64_t max_raycast_pixels = 2048u * 2048u;
  uint32_t mesh_chunk_bytes = 4u << 20;  // at least 1024 are sent per chunk
  std::size_t max_points = std::size_t{1} << 20;
};

}  // namespace semfuse::server
