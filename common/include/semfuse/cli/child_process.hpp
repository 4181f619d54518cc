#pragma once
// A program started by another semfuse program (the ingest bench's server, the tests' servers and
// clients): fork + exec, with the kernel asked to SIGTERM the child when its parent dies
// (PR_SET_PDEATHSIG), so that even a killed parent leaves no process behind. Going out of scope
// ends the child with SIGTERM and reaps it.
#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"

namespace semfuse::cli {

class ChildProcess {
 public:
  // args[0] is the executable's path.
  static Result<std::unique_ptr<ChildProcess>> start(std::vector<std::string> args);
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // True while the child has not exited.
  bool running();
  // Sends `signal` and waits up to `timeout_ms` for the exit, then SIGKILL. Returns the exit
  // code, -1 when the child had to be killed or died from a signal.
  int stop(int signal = 15 /* SIGTERM */, int timeout_ms = 20000);

 private:
  explicit ChildProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_;
  int status_ = 0;
  bool exited_ = false;
};

}  // namespace semfuse::cli
