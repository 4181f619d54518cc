#pragma once
// The server's published state, as the client library names it (the type lives in core/).
#include "semfuse/core/server_status.hpp"

namespace semfuse::client {

using semfuse::CameraStatus;
using semfuse::ReasonCount;
using semfuse::ServerError;
using semfuse::ServerStatus;
using semfuse::StageTiming;
using semfuse::trackingStateName;

}  // namespace semfuse::client
