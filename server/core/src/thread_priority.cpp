#include "thread_priority.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <thread>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace semfuse::server {

void lowerToQueryPriority() {
  thread_local bool lowered = false;
  if (lowered) return;
  lowered = true;
  const auto thread = static_cast<id_t>(gettid());
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, thread);
  if (nice == -1 && errno != 0) return;
  (void)setpriority(PRIO_PROCESS, thread, nice + kQueryNice);
}

void startTbbWorkers() {
  // Every worker must take part: each index waits until all have arrived or a moment has passed
  // (a worker busy elsewhere cannot hold the start up).
  const auto workers = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  std::atomic<std::size_t> arrived{0};
  tbb::parallel_for(std::size_t{0}, workers, [&](std::size_t) {
    ++arrived;
    for (int i = 0; i < 100 && arrived.load() < workers; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
}

}  // namespace semfuse::server
