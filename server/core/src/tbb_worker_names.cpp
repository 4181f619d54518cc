#include "tbb_worker_names.hpp"

#include <tbb/task_scheduler_observer.h>

#include "semfuse/core/thread_name.hpp"

namespace semfuse::server {
namespace {

// Observes the implicit arena of the thread that creates it: TBB calls on_scheduler_entry on
// each worker that comes to help with that thread's parallel work.
class WorkerNamer final : public tbb::task_scheduler_observer {
 public:
  WorkerNamer() { observe(true); }
  ~WorkerNamer() override { observe(false); }

  void on_scheduler_entry(bool is_worker) override {
    // A worker enters arenas over and over; naming it is a write to /proc, so once is enough.
    thread_local bool named = false;
    if (!is_worker || named) return;
    named = true;
    setCurrentThreadName("sf-worker");
  }
};

}  // namespace

void nameTbbWorkers() { thread_local WorkerNamer namer; }

}  // namespace semfuse::server
