#pragma once
// How the map's objects changed from one grouping to the next (the server's object_events topic,
// idl/semfuse/msg.idl ObjectEvents_), as plain C++ values.
#include <cstdint>
#include <string>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse {

// Values as ObjectEvent_Constants on the wire.
enum class ObjectEventKind : uint8_t {
  kAppeared = 0,  // `id` is a new object
  kMerged = 1,    // the objects `others` joined `id` and are gone
  kSplit = 2,     // the new objects `others` came apart from `id`, which goes on
  kVanished = 3,  // `id` is gone (the map was reset or reloaded, or its surface fell apart)
};

const char* objectEventKindName(ObjectEventKind kind);  // "appeared", "merged", "split", "vanished"

struct ObjectEvent {
  ObjectEventKind kind = ObjectEventKind::kAppeared;
  uint32_t id = 0;
  LabelId label = kUnlabeled;  // of `id`
  std::vector<uint32_t> others;
};

// The events of one update of the objects: every update that changed something is numbered.
struct ObjectEvents {
  uint64_t update = 0;        // 1, 2, ... since the server started
  Stamp stamp;                // wall clock of the update
  uint32_t object_count = 0;  // objects after it (fragments not counted)
  std::vector<ObjectEvent> events;
};

}  // namespace semfuse
