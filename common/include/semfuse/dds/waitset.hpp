#pragma once
// WaitSet and the conditions attached to it. A ReadCondition triggers while its reader holds
// samples; a GuardCondition is triggered by hand, e.g. to wake a thread that must stop.
#include <vector>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"
#include "semfuse/dds/entity.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::dds {

class GuardCondition {
 public:
  explicit GuardCondition(const Participant& participant);
  dds_entity_t handle() const { return entity_.handle(); }
  void trigger();
  void reset();
  bool triggered() const;

 private:
  Entity entity_;
};

class ReadCondition {
 public:
  // Triggers while the reader holds samples in any of the given states (default: any).
  explicit ReadCondition(dds_entity_t reader, uint32_t mask = DDS_ANY_STATE);
  dds_entity_t handle() const { return entity_.handle(); }

 private:
  Entity entity_;
};

class WaitSet {
 public:
  explicit WaitSet(const Participant& participant);
  dds_entity_t handle() const { return entity_.handle(); }

  // Attaches a condition (or an entity whose status mask is set); its handle comes back
  // from wait() as the attachment.
  void attach(dds_entity_t condition);
  void detach(dds_entity_t condition);

  // Blocks until a condition triggers or the timeout passes. Returns the handles of the
  // triggered conditions: empty on timeout.
  Result<std::vector<dds_entity_t>> wait(dds_duration_t timeout);

 private:
  Entity entity_;
  std::vector<dds_entity_t> attached_;
};

}  // namespace semfuse::dds
