#pragma once
// What every binding shares: DDS participants (one per domain, shared by the objects that do not
// bring their own), timeouts in seconds, the semfuse exceptions, and the objects with threads of
// their own that must stop before the interpreter does.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // in every file: the casters of std::optional and std::vector must be one

#include "semfuse/client/call_result.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::python {

namespace py = pybind11;

// A participant as Python objects hold it: the last holder destroys it.
using SharedParticipant = std::shared_ptr<dds::Participant>;

// The participant of `domain` (nullopt: Cyclone's default domain) this process shares: created on
// first use, destroyed when no object holds it any more. Raises semfuse.Error when DDS refuses.
SharedParticipant sharedParticipant(std::optional<int> domain);
// The object's participant: the one given, else the shared one of `domain`.
SharedParticipant participantFor(const py::object& participant, std::optional<int> domain);

// Seconds (None: `fallback`) as the client library's milliseconds; raises ValueError on a negative
// or non-finite value.
std::chrono::milliseconds toTimeout(const std::optional<double>& seconds, std::chrono::milliseconds fallback);

// Raises semfuse.Error with the error's message and reason (its code's name).
[[noreturn]] void raiseError(const Error& error);
// Raises what a failed call is: CallTimeout, ServerError (with the reply status) or ClientError.
[[noreturn]] void raiseCallFailure(client::Failure failure, const std::string& message, ErrorCode code);

template <class T>
T valueOrRaise(client::CallResult<T>&& result) {
  if (!result) raiseCallFailure(result.failure(), result.error(), result.errorCode());
  return std::move(result).value();
}

// An object with threads that call into Python (Segmenter, PoseSubscription). Live ones are
// stopped by stopAllThreads(), which the package runs at exit: a thread that tried to take the
// interpreter's lock after the interpreter is gone would hang the process.
class ThreadOwner {
 public:
  ThreadOwner();
  virtual ~ThreadOwner();
  ThreadOwner(const ThreadOwner&) = delete;
  ThreadOwner& operator=(const ThreadOwner&) = delete;
  // Stops the threads; called with the interpreter's lock held.
  virtual void stopThreads() = 0;
};
void stopAllThreads();

// A Python object (a user's callback) that may be released on any thread: taking the
// interpreter's lock to release it.
struct PyObjectHolder {
  explicit PyObjectHolder(py::object o) : object(std::move(o)) {}
  ~PyObjectHolder() {
    if (!Py_IsInitialized()) {
      object.release();  // the interpreter is gone: nothing to give back
      return;
    }
    py::gil_scoped_acquire gil;
    object = py::object();
  }
  PyObjectHolder(const PyObjectHolder&) = delete;
  PyObjectHolder& operator=(const PyObjectHolder&) = delete;
  py::object object;
};

// Describes a Python exception raised in a callback on one of our threads as "Type: message", and
// logs its traceback when it is one of the first kFullTracebacks errors of that owner (`where`:
// "segmenter 'x'"); later ones are the caller's to log, on one line. Called with the
// interpreter's lock held.
inline constexpr uint64_t kFullTracebacks = 3;
std::string describeCallbackError(py::error_already_set& error, uint64_t errors_so_far, const std::string& where);

// The module's bindings, one function per file.
void bindTypes(py::module_& m);
void bindParticipant(py::module_& m);
void bindMapClient(py::module_& m);
void bindSegmenter(py::module_& m);
void bindCameraPublisher(py::module_& m);

}  // namespace semfuse::python
