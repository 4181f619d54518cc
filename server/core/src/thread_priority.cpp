#include "thread_priority.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <thread>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace semfuse::server {
namespace {

// The nice of the process's main thread (its id is the process's), which every tier is above.
int processNice() {
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(getpid()));
  return nice == -1 && errno != 0 ? 0 : nice;
}

void lowerCallingThreadTo(int above_process) {
  const auto thread = static_cast<id_t>(gettid());
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, thread);
  if (nice == -1 && errno != 0) return;
  const int wanted = std::min(processNice() + above_process, 19);
  if (nice < wanted) (void)setpriority(PRIO_PROCESS, thread, wanted);
}

}  // namespace

void lowerToMapPriority() { lowerCallingThreadTo(kMapNice); }
void lowerToQueryPriority() { lowerCallingThreadTo(kQueryNice); }

void startTbbWorkers() {
  // Every worker must take part: each index waits until all have arrived or a moment has passed
  // (a worker busy elsewhere cannot hold the start up). The calling thread keeps its priority.
  const auto workers = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  const pid_t caller = gettid();
  std::atomic<std::size_t> arrived{0};
  tbb::parallel_for(std::size_t{0}, workers, [&](std::size_t) {
    if (gettid() != caller) lowerToMapPriority();
    ++arrived;
    for (int i = 0; i < 100 && arrived.load() < workers; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
}

}  // namespace semfuse::server
