#include "semfuse/core/server_status.hpp"

namespace semfuse {

const char* trackingStateName(uint8_t state) {
  switch (state) {
    case 0:
      return "given";
    case 1:
      return "tracked";
    case 2:
      return "refined";
    case 3:
      return "lost";
    default:
      return "unknown";
  }
}

}  // namespace semfuse
