#include "semfuse/core/malloc_tuning.hpp"

#include <spdlog/spdlog.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace semfuse {

bool keepScratchResident() {
#if defined(__GLIBC__)
  // Setting either also stops glibc from moving the thresholds itself.
  const bool mmap_ok = mallopt(M_MMAP_THRESHOLD, static_cast<int>(kMmapThreshold)) == 1;
  const bool trim_ok = mallopt(M_TRIM_THRESHOLD, static_cast<int>(kTrimThreshold)) == 1;
  if (!mmap_ok || !trim_ok) {
    spdlog::warn("malloc tuning refused (mmap threshold {}, trim threshold {}): queries will page-fault their scratch",
                 mmap_ok ? "set" : "refused", trim_ok ? "set" : "refused");
    return false;
  }
  spdlog::debug("malloc: blocks up to {} MiB from the heap, up to {} MiB of free heap kept", kMmapThreshold >> 20,
                kTrimThreshold >> 20);
#endif
  return true;
}

}  // namespace semfuse
