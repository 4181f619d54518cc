#include "semfuse/dds/match.hpp"

#include "semfuse/dds/entity.hpp"

namespace semfuse::dds {
namespace {

using Getter = int32_t (*)(dds_entity_t);

// Waits on the endpoint's status condition: matching changes raise it, and reading the
// status (in count()) lowers it again, so each change wakes the loop once.
bool waitForCount(dds_entity_t endpoint, uint32_t status, Getter count, int32_t wanted, dds_duration_t timeout) {
  if (count(endpoint) >= wanted) return true;
  const dds_entity_t participant = dds_get_participant(endpoint);
  if (participant < 0) return false;
  Entity waitset(dds_create_waitset(participant));
  if (!waitset) return false;
  uint32_t mask = 0;
  if (dds_get_status_mask(endpoint, &mask) < 0) return false;
  if (dds_set_status_mask(endpoint, mask | status) < 0) return false;
  if (dds_waitset_attach(waitset.handle(), endpoint, endpoint) < 0) return false;
  const dds_time_t deadline = dds_time() + timeout;
  for (;;) {
    if (count(endpoint) >= wanted) return true;
    const dds_time_t now = dds_time();
    if (now >= deadline) return false;
    dds_attach_t triggered = 0;
    if (dds_waitset_wait(waitset.handle(), &triggered, 1, deadline - now) < 0) return false;
  }
}

}  // namespace

int32_t matchedReaders(dds_entity_t writer) {
  dds_publication_matched_status_t status{};
  const dds_return_t rc = dds_get_publication_matched_status(writer, &status);
  return rc < 0 ? rc : static_cast<int32_t>(status.current_count);
}

int32_t readersEverMatched(dds_entity_t writer) {
  dds_publication_matched_status_t status{};
  const dds_return_t rc = dds_get_publication_matched_status(writer, &status);
  return rc < 0 ? rc : static_cast<int32_t>(status.total_count);
}

int32_t matchedWriters(dds_entity_t reader) {
  dds_subscription_matched_status_t status{};
  const dds_return_t rc = dds_get_subscription_matched_status(reader, &status);
  return rc < 0 ? rc : static_cast<int32_t>(status.current_count);
}

bool waitForReaders(dds_entity_t writer, int32_t count, dds_duration_t timeout) {
  return waitForCount(writer, DDS_PUBLICATION_MATCHED_STATUS, matchedReaders, count, timeout);
}

bool waitForWriters(dds_entity_t reader, int32_t count, dds_duration_t timeout) {
  return waitForCount(reader, DDS_SUBSCRIPTION_MATCHED_STATUS, matchedWriters, count, timeout);
}

}  // namespace semfuse::dds
