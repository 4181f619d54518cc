#include "semfuse/dds/waitset.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "semfuse/dds/error.hpp"

namespace semfuse::dds {

GuardCondition::GuardCondition(const Participant& participant)
    : entity_(check(dds_create_guardcondition(participant.handle()), "create guard condition")) {}

void GuardCondition::trigger() { check(dds_set_guardcondition(entity_.handle(), true), "trigger guard condition"); }
void GuardCondition::reset() { check(dds_set_guardcondition(entity_.handle(), false), "reset guard condition"); }
bool GuardCondition::triggered() const {
  bool value = false;
  check(dds_read_guardcondition(entity_.handle(), &value), "read guard condition");
  return value;
}

ReadCondition::ReadCondition(dds_entity_t reader, uint32_t mask)
    : entity_(check(dds_create_readcondition(reader, mask), "create read condition")) {}

WaitSet::WaitSet(const Participant& participant)
    : entity_(check(dds_create_waitset(participant.handle()), "create waitset")) {}

void WaitSet::attach(dds_entity_t condition) {
  check(dds_waitset_attach(entity_.handle(), condition, condition), "attach to waitset");
  attached_.push_back(condition);
}

void WaitSet::detach(dds_entity_t condition) {
  check(dds_waitset_detach(entity_.handle(), condition), "detach from waitset");
  attached_.erase(std::remove(attached_.begin(), attached_.end(), condition), attached_.end());
}

Result<std::vector<dds_entity_t>> WaitSet::wait(dds_duration_t timeout) {
  // One slot per attached condition: every triggered one fits.
  std::vector<dds_attach_t> triggered(std::max<std::size_t>(attached_.size(), 1));
  const dds_return_t n = dds_waitset_wait(entity_.handle(), triggered.data(), triggered.size(), timeout);
  if (n < 0) return makeError(describe("wait on waitset", n));
  std::vector<dds_entity_t> handles;
  handles.reserve(static_cast<std::size_t>(n));
  for (dds_return_t i = 0; i < n && static_cast<std::size_t>(i) < triggered.size(); ++i) {
    handles.push_back(static_cast<dds_entity_t>(triggered[static_cast<std::size_t>(i)]));
  }
  return handles;
}

}  // namespace semfuse::dds
