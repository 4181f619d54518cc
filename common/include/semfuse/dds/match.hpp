#pragma once
// Waiting for discovery: a writer or reader is useful only once the other side is matched,
// and discovery takes a few hundred milliseconds on a quiet host.
#include <cstdint>

#include <dds/dds.h>

namespace semfuse::dds {

// Current number of matched readers (of a writer) or writers (of a reader); negative on error.
int32_t matchedReaders(dds_entity_t writer);
int32_t matchedWriters(dds_entity_t reader);
// Readers a writer has matched since it was created, those gone included; negative on error.
int32_t readersEverMatched(dds_entity_t writer);

// Block until at least `count` remote endpoints are matched or the timeout passes.
bool waitForReaders(dds_entity_t writer, int32_t count, dds_duration_t timeout);
bool waitForWriters(dds_entity_t reader, int32_t count, dds_duration_t timeout);

}  // namespace semfuse::dds
