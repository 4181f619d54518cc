#include "runtime.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include <spdlog/spdlog.h>

#include "semfuse/core/service_types.hpp"
#include "semfuse/dds/error.hpp"

namespace semfuse::python {
namespace {

std::mutex& participantsMutex() {
  static std::mutex mutex;
  return mutex;
}
std::map<int, std::weak_ptr<dds::Participant>>& participantsByDomain() {
  static std::map<int, std::weak_ptr<dds::Participant>> participants;
  return participants;
}

std::mutex& ownersMutex() {
  static std::mutex mutex;
  return mutex;
}
std::set<ThreadOwner*>& liveOwners() {
  static std::set<ThreadOwner*> owners;
  return owners;
}

py::object errorClass(const char* name) { return py::module_::import("semfuse._errors").attr(name); }

[[noreturn]] void raise(const py::object& exception) {
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exception.ptr())), exception.ptr());
  throw py::error_already_set();
}

// A participant of `domain`, created without the interpreter's lock (Cyclone starts its threads
// and discovery there); DDS's refusal becomes semfuse.Error.
SharedParticipant createParticipant(std::optional<int> domain) {
  try {
    py::gil_scoped_release release;
    return std::make_shared<dds::Participant>(domain ? static_cast<dds_domainid_t>(*domain) : DDS_DOMAIN_DEFAULT);
  } catch (const dds::DdsError& e) {
    raiseError(makeError(ErrorCode::kUnavailable, e.what()));
  }
}

void checkDomain(std::optional<int> domain) {
  if (domain && (*domain < 0 || *domain > 232)) throw py::value_error("domain_id must be in 0..232");
}

class Participant {
 public:
  Participant(std::optional<int> domain, const std::optional<std::string>& dds_profile) {
    if (dds_profile) {
      const auto path = std::filesystem::absolute(*dds_profile);
      if (!std::filesystem::is_regular_file(path)) throw py::value_error("dds_profile: no file " + path.string());
      const std::string uri = "file://" + path.string();
      ::setenv("CYCLONEDDS_URI", uri.c_str(), 1);
      checkDomain(domain);
      participant_ = createParticipant(domain);
    } else {
      participant_ = sharedParticipant(domain);
    }
  }
  const SharedParticipant& get() const { return participant_; }
  int domain() const { return static_cast<int>(participant_->domain()); }

 private:
  SharedParticipant participant_;
};

}  // namespace

SharedParticipant sharedParticipant(std::optional<int> domain) {
  checkDomain(domain);
  try {
    // The registry's lock is taken without the interpreter's: a thread waiting for it must not
    // hold the lock the thread creating a participant needs to come back.
    py::gil_scoped_release release;
    std::lock_guard lock(participantsMutex());
    std::weak_ptr<dds::Participant>& slot = participantsByDomain()[domain ? *domain : -1];
    if (auto existing = slot.lock()) return existing;
    auto created =
        std::make_shared<dds::Participant>(domain ? static_cast<dds_domainid_t>(*domain) : DDS_DOMAIN_DEFAULT);
    slot = created;
    return created;
  } catch (const dds::DdsError& e) {
    raiseError(makeError(ErrorCode::kUnavailable, e.what()));
  }
}

SharedParticipant participantFor(const py::object& participant, std::optional<int> domain) {
  if (participant.is_none()) return sharedParticipant(domain);
  if (domain) throw py::value_error("give either participant or domain_id, not both");
  return participant.cast<const Participant&>().get();
}

std::chrono::milliseconds toTimeout(const std::optional<double>& seconds, std::chrono::milliseconds fallback) {
  if (!seconds) return fallback;
  if (!std::isfinite(*seconds) || *seconds < 0.0) throw py::value_error("a timeout is a number of seconds >= 0");
  return std::chrono::milliseconds(static_cast<int64_t>(std::llround(*seconds * 1000.0)));
}

void raiseError(const Error& error) { raise(errorClass("Error")(error.message, errorCodeName(error.code))); }

void raiseCallFailure(client::Failure failure, const std::string& message, ErrorCode code) {
  switch (failure) {
    case client::Failure::kTimeout:
      raise(errorClass("CallTimeout")(message, errorCodeName(code)));
    case client::Failure::kServer:
      raise(errorClass("ServerError")(message, errorCodeName(code), static_cast<int>(replyCodeOf(code))));
    case client::Failure::kClient:
    case client::Failure::kNone:
      break;
  }
  raise(errorClass("ClientError")(message, errorCodeName(code)));
}

ThreadOwner::ThreadOwner() {
  std::lock_guard lock(ownersMutex());
  liveOwners().insert(this);
}

ThreadOwner::~ThreadOwner() {
  std::lock_guard lock(ownersMutex());
  liveOwners().erase(this);
}

void stopAllThreads() {
  std::vector<ThreadOwner*> owners;
  {
    std::lock_guard lock(ownersMutex());
    owners.assign(liveOwners().begin(), liveOwners().end());
  }
  // Owners are Python objects: none is destroyed while this runs, the interpreter's lock is held.
  for (ThreadOwner* owner : owners) owner->stopThreads();
}

std::string describeCallbackError(py::error_already_set& error, uint64_t errors_so_far, const std::string& where) {
  const std::string type = py::str(error.type().attr("__name__")).cast<std::string>();
  const std::string line = type + ": " + py::str(error.value()).cast<std::string>();
  if (errors_so_far >= kFullTracebacks) return line;
  std::string traceback;
  try {
    const py::object format = py::module_::import("traceback").attr("format_exception");
    for (const auto& part : format(error.type(), error.value(), error.trace())) traceback += part.cast<std::string>();
  } catch (const py::error_already_set&) {
    traceback = line + "\n";
  }
  spdlog::warn("{}: the callback raised{}\n{}", where,
               errors_so_far + 1 == kFullTracebacks ? " (tracebacks of later errors are not shown)" : "", traceback);
  return line;
}

void bindParticipant(py::module_& m) {
  py::class_<Participant>(m, "Participant", R"doc(
A DDS domain participant. MapClient, Segmenter and CameraPublisher share one per domain when none
is given; create one yourself to apply a Cyclone DDS profile or to keep a domain's discovery alive
between objects.

Cyclone reads its configuration when a domain's first participant is created: ``dds_profile``
(an XML file, e.g. ``deploy/dds/localhost.xml``) sets ``CYCLONEDDS_URI`` before creating it, and
has no effect on a domain this process already joined.
)doc")
      .def(py::init<std::optional<int>, const std::optional<std::string>&>(), py::arg("domain_id") = py::none(),
           py::arg("dds_profile") = py::none(),
           "Joins DDS domain ``domain_id`` (None: Cyclone's default domain). Raises semfuse.Error when DDS "
           "refuses (a bad profile).")
      .def_property_readonly("domain_id", &Participant::domain, "The DDS domain id.")
      .def("__repr__",
           [](const Participant& p) { return "semfuse.Participant(domain_id=" + std::to_string(p.domain()) + ")"; });
}

}  // namespace semfuse::python
