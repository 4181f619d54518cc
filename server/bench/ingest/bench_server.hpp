#pragma once
// The semfuse-server a bench drives: started as a child process on a DDS domain of its own with
// the loopback profile (set for this process's participants too, before the first one exists),
// logging warnings only (unless the extra arguments give --log-level), plus the bench's extra
// arguments.
#include <memory>
#include <string>
#include <vector>

#include "semfuse/cli/child_process.hpp"
#include "semfuse/core/result.hpp"

namespace semfuse::bench::ingest {

struct BenchServer {
  std::unique_ptr<cli::ChildProcess> process;
  int domain = 0;
};

// domain -1 = one derived from this process's pid. cpus: a CPU list the server runs on
// (taskset -c), "" for every core.
Result<BenchServer> startBenchServer(const std::string& executable, int domain,
                                     const std::vector<std::string>& extra_args, const std::string& cpus = "");

}  // namespace semfuse::bench::ingest
