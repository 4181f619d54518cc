#include "process_memory.hpp"

#include <unistd.h>
#include <fstream>

namespace semfuse::server {

uint64_t currentRssBytes() {
  std::ifstream statm("/proc/self/statm");
  uint64_t pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0;
  return pages_resident * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

}  // namespace semfuse::server
