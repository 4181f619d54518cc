#pragma once
// PeriodicThread: one thread that runs a round every period, on a fixed schedule (a round that
// overran starts the next at once, not a burst), at the queries' priority (thread_priority.hpp),
// until stop(). The live mesh's updater and the objects' refresher run on one each.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace semfuse::server {

class PeriodicThread {
 public:
  PeriodicThread() = default;
  ~PeriodicThread() { stop(); }
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;

  // Starts the thread `name`; a round that throws is logged and the next runs as planned.
  void start(std::string name, std::chrono::steady_clock::duration period, std::function<void()> round);
  // Waits for a round in progress; nothing when not started.
  void stop();

 private:
  void run(std::chrono::steady_clock::duration period);

  std::string name_;
  std::function<void()> round_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool running_ = false;  // under mutex_
  std::thread thread_;
};

}  // namespace semfuse::server
