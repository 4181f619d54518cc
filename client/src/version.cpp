#include "semfuse/client/version.hpp"

namespace semfuse::client {
const char* version() { return SEMFUSE_VERSION; }
}  // namespace semfuse::client
