#pragma once
// Telling a server's reader from any other reader of a topic. A segmenter also reads
// rt/semfuse/frames, so "the frames writer has a matched reader" does not mean the server is
// there; a camera that started publishing on that basis would lose its first frames to the
// server's discovery. The server is the participant that publishes rt/semfuse/status.
#include <chrono>
#include <optional>

#include <dds/dds.h>

#include "semfuse/dds/participant.hpp"

namespace semfuse::client::detail {

// The participant key of a semfuse server on the participant's domain: the publisher of the
// first status sample received within `timeout` (status is transient-local, so a running server's
// latest sample arrives as soon as it is discovered). nullopt when none shows up.
std::optional<dds_guid_t> findServerParticipant(const dds::Participant& participant, std::chrono::milliseconds timeout);

// Waits until `writer` is matched with a reader of the participant `key`, or the timeout.
bool waitForReaderOf(dds_entity_t writer, const dds_guid_t& key, std::chrono::milliseconds timeout);

}  // namespace semfuse::client::detail
