// The TBB workers that help a server thread are named "sf-worker" (tbb_worker_names.hpp), not
// after the thread that happened to start them.
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"

namespace semfuse::server {
namespace {

std::string threadName(long tid) {
  std::ifstream comm("/proc/self/task/" + std::to_string(tid) + "/comm");
  std::string name;
  std::getline(comm, name);
  return name;
}

TEST(TbbWorkerNames, AWorkerThatHelpsIsNamedSfWorker) {
  if (tbb::this_task_arena::max_concurrency() < 2) GTEST_SKIP() << "TBB has no worker thread here";
  long owner_tid = 0, helper_tid = 0;
  std::string helper_name;
  bool met = false;
  std::thread owner([&] {
    setCurrentThreadName("sf-test-owner");
    nameTbbWorkers();
    owner_tid = syscall(SYS_gettid);
    // Two chunks that wait for each other: the owner runs one, so a worker must run the other.
    std::atomic<int> arrived{0};
    std::atomic<long> other{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, 2, 1), [&](const tbb::blocked_range<int>&) {
      const long tid = syscall(SYS_gettid);
      if (tid != owner_tid) other = tid;
      ++arrived;
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (arrived.load() < 2 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
    });
    met = arrived.load() == 2;
    helper_tid = other.load();
    // Read while this thread lives: when the only thread that used TBB exits, TBB may end its
    // workers, and the helper's /proc entry with them.
    if (helper_tid != 0) helper_name = threadName(helper_tid);
  });
  owner.join();
  ASSERT_TRUE(met) << "no TBB worker joined within 10 s";
  ASSERT_NE(helper_tid, 0);
  EXPECT_EQ(helper_name, "sf-worker");
}

}  // namespace
}  // namespace semfuse::server
