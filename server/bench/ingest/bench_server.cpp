#include "bench_server.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace semfuse::bench::ingest {

Result<BenchServer> startBenchServer(const std::string& executable, int domain,
                                     const std::vector<std::string>& extra_args, const std::string& cpus) {
  if (executable.empty() || ::access(executable.c_str(), X_OK) != 0)
    return makeError("semfuse-server not found at '" + executable + "' (use --server)");
  const std::string profile = std::string(SEMFUSE_SOURCE_DIR) + "/deploy/dds/localhost.xml";
  ::setenv("CYCLONEDDS_URI", ("file://" + profile).c_str(), 1);  // before the first participant
  BenchServer server;
  server.domain = domain >= 0 ? domain : 200 + static_cast<int>(::getpid() % 30);
  std::vector<std::string> args{executable, "--domain-id", std::to_string(server.domain), "--dds-profile", profile};
  // Warnings only, unless the bench's arguments ask for another level (the server takes one).
  const bool level_given = std::any_of(extra_args.begin(), extra_args.end(),
                                       [](const std::string& arg) { return arg.rfind("--log-level", 0) == 0; });
  if (!level_given) args.insert(args.end(), {"--log-level", "warn"});
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  if (!cpus.empty()) {
    // taskset execs the server in its place: the child's pid stays the server's.
    const char* taskset = "/usr/bin/taskset";
    if (::access(taskset, X_OK) != 0) return makeError("--server-cpus needs taskset (Debian util-linux)");
    args.insert(args.begin(), {taskset, "-c", cpus});
  }
  std::printf("server: %s (domain %d)%s\n", executable.c_str(), server.domain,
              cpus.empty() ? "" : (" on CPUs " + cpus).c_str());
  auto process = cli::ChildProcess::start(args);
  if (!process) return makeError(process.error());
  server.process = std::move(process).value();
  return server;
}

}  // namespace semfuse::bench::ingest
