#pragma once
// The wire form of ServerStatus (semfuse/core/server_status.hpp): published on rt/semfuse/status
// and returned by the admin service.
#include <cstdint>
#include "msg.h"
#include "semfuse/core/server_status.hpp"

namespace semfuse::server {

// Fills `out` (whose strings and sequences are freed first by the caller, e.g. Sample::clear)
// with dds_alloc'd copies, so it can be written or freed with dds_sample_free.
void fillStatusMessage(const ServerStatus& status, semfuse_msg_dds__ServerStatus_& out);

// Resident set size of this process, bytes (0 where /proc is not readable).
uint64_t currentRssBytes();

}  // namespace semfuse::server
