// The server's CPU priorities (thread_priority.hpp): the main thread (and the pose threads it
// starts) keep the process's priority, a map thread runs kMapNice below it and a query thread
// kQueryNice below it, however often they ask, and the TBB workers started beforehand run at the
// map's priority also when they help a query thread. Its own program: TBB's workers are started
// once per process.
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "thread_priority.hpp"

namespace semfuse::server {
namespace {

int niceOf(pid_t thread) { return getpriority(PRIO_PROCESS, static_cast<id_t>(thread)); }

TEST(ThreadPriority, PoseThenMapThenQueryThreads) {
  const pid_t main_thread = gettid();
  const int base = niceOf(main_thread);
  startTbbWorkers();
  int fusion_nice = 0, lowered_twice_nice = 0;
  std::thread fusion([&] {
    lowerToMapPriority();
    fusion_nice = niceOf(gettid());
  });
  fusion.join();
  EXPECT_EQ(fusion_nice, std::min(base + kMapNice, 19));
  std::thread lowered_twice([&] {
    lowerToQueryPriority();
    lowerToMapPriority();  // never raises it again
    lowered_twice_nice = niceOf(gettid());
  });
  lowered_twice.join();
  EXPECT_EQ(lowered_twice_nice, std::min(base + kQueryNice, 19));

  int query_nice = 0, helper_nice = 0;
  bool helped = false;
  std::thread query([&] {
    lowerToQueryPriority();
    lowerToQueryPriority();  // once per thread
    const pid_t self = gettid();
    query_nice = niceOf(self);
    // Two chunks that wait for each other: the query thread runs one, a worker the other.
    std::atomic<int> arrived{0};
    std::atomic<pid_t> other{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, 2, 1), [&](const tbb::blocked_range<int>&) {
      if (gettid() != self) other = gettid();
      ++arrived;
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (arrived.load() < 2 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
    });
    helped = other.load() != 0;
    if (helped) helper_nice = niceOf(other.load());
  });
  query.join();
  EXPECT_EQ(query_nice, std::min(base + kQueryNice, 19));
  EXPECT_EQ(niceOf(main_thread), base);
  if (tbb::this_task_arena::max_concurrency() < 2) GTEST_SKIP() << "TBB has no worker thread here";
  ASSERT_TRUE(helped);
  EXPECT_EQ(helper_nice, std::min(base + kMapNice, 19));
}

}  // namespace
}  // namespace semfuse::server
