#include "semfuse/core/object_events.hpp"

namespace semfuse {

const char* objectEventKindName(ObjectEventKind kind) {
  switch (kind) {
    case ObjectEventKind::kAppeared:
      return "appeared";
    case ObjectEventKind::kMerged:
      return "merged";
    case ObjectEventKind::kSplit:
      return "split";
    case ObjectEventKind::kVanished:
      return "vanished";
  }
  return "unknown";
}

}  // namespace semfuse
