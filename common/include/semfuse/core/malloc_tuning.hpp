#pragma once
// For long-running processes that serve queries (semfuse-server; semfuse-bench, to time the
// library as the server runs it). Every raycast query allocates tens of MB of scratch (the copy
// of the leaves in view, the TSDF bricks, the per-pixel bounds, the images, the reply). glibc
// serves blocks that large with mmap, or trims them off the heap as soon as they are freed, so
// the next query takes all those pages again from the kernel: on the 7-Scenes map about 12,000
// page faults per raycast, ~10 ms of a 45 ms raycast.
// keepScratchResident() makes glibc keep freed memory for reuse instead (up to a bound), so a
// steady stream of queries faults nothing.
#include <cstddef>

namespace semfuse {

// Blocks up to kMmapThreshold come from the heap (glibc's cap; larger ones are mapped each
// time), and up to kTrimThreshold of free memory at the top of a heap is kept. No-op off glibc.
inline constexpr std::size_t kMmapThreshold = std::size_t{32} << 20;
inline constexpr std::size_t kTrimThreshold = std::size_t{256} << 20;

// Call once, first thing in main(). False (with the reason logged) when glibc refused a setting.
bool keepScratchResident();

}  // namespace semfuse
