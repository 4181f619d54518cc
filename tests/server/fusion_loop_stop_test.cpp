// The fusion loop's part in the server's stop sequence: once it takes no more tasks, an admin
// load or reset posted to it is refused at once instead of waiting out its timeout, a task that
// is running finishes, and a task no thread will run is answered when the loop stops.
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "fusion_loop.hpp"
#include "mapper.hpp"
#include "server_state.hpp"
#include "wall_scene.hpp"

using namespace semfuse;
using namespace semfuse::server;
using namespace semfuse::server::wall_scene;
using namespace std::chrono_literals;

namespace {

// What the admin service waits for a task; long enough that waiting it out fails every check below.
constexpr auto kTaskTimeout = 10s;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A task that only notes that it ran.
std::function<Status()> noting(std::atomic<bool>& ran) {
  return [&ran] {
    ran = true;
    return Status::Ok();
  };
}

struct Loop {
  Mapper mapper{wallMapOptions()};
  FrameQueue frames{4};
  ServerState state;
  FusionLoop loop{mapper, frames, state, FusionLimits{}, nullptr};
};

}  // namespace

TEST(FusionLoopStop, ATaskPostedAfterTheLoopStoppedIsRefusedAtOnce) {
  Loop l;
  l.loop.start();
  l.loop.stop();
  std::atomic<bool> ran{false};
  const auto start = std::chrono::steady_clock::now();
  Status late = l.loop.runOnFusionThread(noting(ran), kTaskTimeout);
  EXPECT_LT(secondsSince(start), 1.0);
  ASSERT_FALSE(late.ok());
  EXPECT_EQ(late.errorCode(), ErrorCode::kUnavailable) << late.error();
  EXPECT_NE(late.error().find("shutting down"), std::string::npos) << late.error();
  EXPECT_FALSE(ran);
}

TEST(FusionLoopStop, ClosedToTasksItRefusesNewOnesAtOnceAndFinishesTheRunningOne) {
  Loop l;
  l.loop.start();
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> running{false};
  auto first = std::async(std::launch::async, [&] {
    return l.loop.runOnFusionThread(
        [&] {
          running = true;
          released.wait();
          return Status::Ok();
        },
        kTaskTimeout);
  });
  for (int i = 0; i < 500 && !running; ++i) std::this_thread::sleep_for(10ms);
  ASSERT_TRUE(running);
  EXPECT_FALSE(l.loop.idle());  // a running task counts as work in progress: the stop sequence waits for it

  l.loop.closeTasks();
  std::atomic<bool> second_ran{false};
  const auto start = std::chrono::steady_clock::now();
  Status second = l.loop.runOnFusionThread(noting(second_ran), kTaskTimeout);
  EXPECT_LT(secondsSince(start), 1.0);
  EXPECT_EQ(second.errorCode(), ErrorCode::kUnavailable) << second.error();

  release.set_value();
  Status first_result = first.get();
  EXPECT_TRUE(first_result.ok()) << first_result.error();
  l.loop.stop();
  EXPECT_FALSE(second_ran);
}

TEST(FusionLoopStop, ATaskNoThreadWillRunIsAnsweredWhenTheLoopStops) {
  Loop l;  // never started: a task posted to it waits for a thread that will not come
  std::atomic<bool> ran{false};
  auto waiting = std::async(std::launch::async, [&] { return l.loop.runOnFusionThread(noting(ran), kTaskTimeout); });
  std::this_thread::sleep_for(100ms);
  const auto stop = std::chrono::steady_clock::now();
  l.loop.stop();
  ASSERT_EQ(waiting.wait_for(2s), std::future_status::ready) << "the caller still waits after the loop stopped";
  EXPECT_LT(secondsSince(stop), 2.0);
  Status result = waiting.get();
  EXPECT_EQ(result.errorCode(), ErrorCode::kUnavailable) << result.error();
  EXPECT_FALSE(ran);
}
