#include "semfuse/cli/child_process.hpp"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace semfuse::cli {

Result<std::unique_ptr<ChildProcess>> ChildProcess::start(std::vector<std::string> args) {
  if (args.empty()) return makeError(ErrorCode::kInvalidArgument, "no program to start");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return makeError("cannot start " + args[0] + ": fork failed");
  if (pid == 0) {  // child: only async-signal-safe calls until exec
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return std::unique_ptr<ChildProcess>(new ChildProcess(pid));
}

bool ChildProcess::running() {
  if (exited_) return false;
  if (::waitpid(pid_, &status_, WNOHANG) == 0) return true;
  exited_ = true;
  return false;
}

int ChildProcess::stop(int signal, int timeout_ms) {
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

}  // namespace semfuse::cli
