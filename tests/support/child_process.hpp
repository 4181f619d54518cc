#pragma once
// ChildProcess for tests: semfuse::cli::ChildProcess started from a constructor that throws when
// the program cannot be started, so that a test reads `ChildProcess server({exe, args...})`.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "semfuse/cli/child_process.hpp"

namespace semfuse::testing {

class ChildProcess {
 public:
  explicit ChildProcess(std::vector<std::string> args) {
    auto started = cli::ChildProcess::start(std::move(args));
    if (!started) throw std::runtime_error(started.error());
    process_ = std::move(started).value();
  }
  bool running() { return process_->running(); }
  int stop(int signal = 15 /* SIGTERM */, int timeout_ms = 20000) { return process_->stop(signal, timeout_ms); }
  pid_t pid() const { return process_->pid(); }

 private:
  std::unique_ptr<cli::ChildProcess> process_;
};

}  // namespace semfuse::testing
