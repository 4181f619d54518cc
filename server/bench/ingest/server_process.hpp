#pragma once
// The semfuse-server process the ingest bench measures. fork + exec rather than posix_spawn so
// that the child can ask the kernel to SIGTERM it when the bench dies (PR_SET_PDEATHSIG): even a
// killed bench leaves no server.
#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"

namespace semfuse::bench::ingest {

class ServerProcess {
 public:
  // args[0] is the executable.
  static Result<std::unique_ptr<ServerProcess>> start(std::vector<std::string> args);
  ~ServerProcess() { stop(); }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  // SIGTERM (the server saves nothing without --map, so it should exit quickly), SIGKILL after
  // 20 s. Returns the exit code, -1 when killed or died from a signal.
  int stop();

 private:
  explicit ServerProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_;
  int status_ = 0;
  bool exited_ = false;
};

}  // namespace semfuse::bench::ingest
