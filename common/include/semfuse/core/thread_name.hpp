#pragma once
// Names the calling thread, so that top -H, perf, gdb and /proc/<pid>/task/*/comm say which of a
// server's threads burns the CPU ("sf-fusion", "sf-ingest", ...). Linux keeps at most 15
// characters; longer names are cut there rather than refused.
#include <string_view>

namespace semfuse {

void setCurrentThreadName(std::string_view name);

}  // namespace semfuse
