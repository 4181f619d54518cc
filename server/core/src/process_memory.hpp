#pragma once
// What the server reports of its own memory in its status.
#include <cstdint>

namespace semfuse::server {

// Resident set size of this process, bytes (0 where /proc is not readable).
uint64_t currentRssBytes();

}  // namespace semfuse::server
