#pragma once
// Service reply statuses (srv.idl's Status_Constants) and error codes, both ways: the server
// answers a failed request with the status of its error's code, and the client hands the caller
// the code of the status it got, so neither side reads the other's messages.
#include <cstdint>

#include "semfuse/core/result.hpp"

namespace semfuse::wire {

// The non-OK status for an error of `code`: replyCodeOf (semfuse/core/service_types.hpp), whose
// codes are the statuses' values. A code the wire has no status for goes to the nearest one:
// kUnspecified to INTERNAL (an unclassified failure of the server).
int32_t replyStatusOf(ErrorCode code);

// The code of a non-OK status; a status this build does not know (a newer server) is kUnspecified.
ErrorCode errorCodeOfReplyStatus(int32_t status);

}  // namespace semfuse::wire
