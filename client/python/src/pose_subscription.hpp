#pragma once
// The server's poses delivered to a Python callback on a thread of its own (MapClient.subscribe_poses).
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <pybind11/pybind11.h>

#include "runtime.hpp"
#include "semfuse/client/map_client.hpp"

namespace semfuse::python {

// What a MapClient shares with its pose iterators and subscription: the client library's client
// (and the participant it needs), and whether a subscription takes the poses.
struct PoseSource {
  SharedParticipant participant;
  std::shared_ptr<client::MapClient> client;
  std::atomic<bool> subscribed{false};

  // Raises RuntimeError while a subscription takes the poses.
  void checkNotSubscribed() const;
};

class PoseSubscription : public ThreadOwner {
 public:
  // Raises RuntimeError when the source already has a subscription.
  PoseSubscription(std::shared_ptr<PoseSource> source, py::function callback);
  ~PoseSubscription() override;

  // Stops the thread after the pose in hand; from inside the callback, after the callback returns.
  void close();
  void stopThreads() override { close(); }
  bool closed() const { return stopping_; }
  uint64_t delivered() const { return delivered_; }
  uint64_t callbackErrors() const { return errors_; }
  std::string lastError() const;

 private:
  void run();

  std::shared_ptr<PoseSource> source_;
  std::shared_ptr<PyObjectHolder> callback_;
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> delivered_{0};
  std::atomic<uint64_t> errors_{0};
  mutable std::mutex mutex_;
  std::string last_error_;
  std::thread thread_;
};

void bindPoseSubscription(py::module_& m);

}  // namespace semfuse::python
