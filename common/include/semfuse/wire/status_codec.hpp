#pragma once
// ServerStatus (semfuse/core/server_status.hpp) <-> semfuse::msg::dds_::ServerStatus_: published on
// rt/semfuse/status and carried by every admin reply.
#include <msg.h>

#include "semfuse/core/result.hpp"
#include "semfuse/core/server_status.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::wire {

// Fills `out` with dds_alloc'd copies (its strings and sequences are replaced, so pass a zeroed
// struct or one Cyclone allocated, e.g. *dds::Sample), so it can be written or freed with
// dds_sample_free. The header carries `stamp` and frame "world".
void encodeServerStatus(const ServerStatus& status, Stamp stamp, semfuse_msg_dds__ServerStatus_& out);

// Rejects sequences that do not hold what they declare. Values are taken as they are: a
// tracking state this version does not know reads as "unknown" (trackingStateName).
Result<ServerStatus> decodeServerStatus(const semfuse_msg_dds__ServerStatus_& msg);

}  // namespace semfuse::wire
