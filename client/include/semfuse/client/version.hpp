#pragma once
// Version of the semfuse client library, for logs and compatibility checks.
namespace semfuse::client {
const char* version();
}  // namespace semfuse::client
