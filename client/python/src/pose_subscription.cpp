#include "pose_subscription.hpp"

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"

namespace semfuse::python {

void PoseSource::checkNotSubscribed() const {
  if (subscribed) throw std::runtime_error("a pose subscription of this MapClient takes its poses; close it first");
}

PoseSubscription::PoseSubscription(std::shared_ptr<PoseSource> source, py::function callback)
    : source_(std::move(source)), callback_(std::make_shared<PyObjectHolder>(std::move(callback))) {
  if (source_->subscribed.exchange(true)) throw std::runtime_error("this MapClient already has a pose subscription");
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-py-poses");
    run();
  });
}

PoseSubscription::~PoseSubscription() {
  close();
  if (thread_.joinable()) thread_.detach();  // closed from its own callback: it ends by itself
}

void PoseSubscription::run() {
  while (!stopping_) {
    std::vector<TrackedPose> poses = source_->client->takePoses(std::chrono::milliseconds(100));
    if (poses.empty() || stopping_) continue;
    py::gil_scoped_acquire gil;
    for (const TrackedPose& pose : poses) {
      try {
        callback_->object(pose);
        ++delivered_;
      } catch (py::error_already_set& e) {
        const std::string line = describeCallbackError(e, errors_, "pose subscription");
        if (errors_ >= kFullTracebacks) spdlog::warn("pose subscription: the callback raised {}", line);
        ++errors_;
        std::lock_guard lock(mutex_);
        last_error_ = line;
      } catch (const std::exception& e) {
        spdlog::warn("pose subscription: the callback failed: {}", e.what());
        ++errors_;
        std::lock_guard lock(mutex_);
        last_error_ = e.what();
      }
    }
  }
}

void PoseSubscription::close() {
  stopping_ = true;
  if (thread_.joinable() && std::this_thread::get_id() != thread_.get_id()) {
    py::gil_scoped_release release;
    thread_.join();
  }
  source_->subscribed = false;
}

std::string PoseSubscription::lastError() const {
  std::lock_guard lock(mutex_);
  return last_error_;
}

void bindPoseSubscription(py::module_& m) {
  py::class_<PoseSubscription>(m, "PoseSubscription",
                               "Delivers the server's poses to a callback (MapClient.subscribe_poses); a context "
                               "manager that closes on exit.")
      .def("close", &PoseSubscription::close, "Stops the deliveries; the callback is not called after close() returns.")
      .def_property_readonly("closed", &PoseSubscription::closed)
      .def_property_readonly("delivered", &PoseSubscription::delivered, "Poses the callback took without raising.")
      .def_property_readonly("callback_errors", &PoseSubscription::callbackErrors, "Calls that raised.")
      .def_property_readonly("last_error", &PoseSubscription::lastError, "The last error's 'Type: message', or ''.")
      .def("__enter__", [](PoseSubscription& s) -> PoseSubscription& { return s; })
      .def("__exit__", [](PoseSubscription& s, const py::args&) { s.close(); });
}

}  // namespace semfuse::python
