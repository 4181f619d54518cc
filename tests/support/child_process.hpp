#pragma once
// ChildProcess: runs an executable and, when it goes out of scope, ends it with SIGTERM and
// reaps it, so a failing test never leaves a process behind.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace semfuse::testing {

class ChildProcess {
 public:
  explicit ChildProcess(std::vector<std::string> args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (::posix_spawn(&pid_, argv[0], nullptr, nullptr, argv.data(), environ) != 0) {
      throw std::runtime_error("cannot start " + args[0]);
    }
  }
  ~ChildProcess() { stop(SIGTERM, 10000); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // True while the child has not exited.
  bool running() {
    if (exited_) return false;
    if (::waitpid(pid_, &status_, WNOHANG) == 0) return true;
    exited_ = true;
    return false;
  }

  // Sends `signal` and waits up to `timeout_ms` for the exit; returns the exit code, or -1 when
  // the child had to be killed or died from a signal.
  int stop(int signal = SIGTERM, int timeout_ms = 20000) {
    if (!exited_) {
      ::kill(pid_, signal);
      for (int waited = 0; waited < timeout_ms && running(); waited += 10) ::usleep(10000);
      if (!exited_) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status_, 0);
        exited_ = true;
        return -1;
      }
    }
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
  }

  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = 0;
  int status_ = 0;
  bool exited_ = false;
};

}  // namespace semfuse::testing
