// The native part of the semfuse Python package (semfuse._semfuse): the client library's
// MapClient, Segmenter and CameraPublisher with numpy arrays. The package's __init__.py re-exports
// it with the exceptions of _errors.py; _semfuse.pyi describes it to editors.
#include <pybind11/pybind11.h>

#include <spdlog/spdlog.h>

#include "runtime.hpp"
#include "semfuse/client/version.hpp"
#include "semfuse/core/logging.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_semfuse, m) {
  using namespace semfuse::python;
  m.doc() = "semfuse client library bindings: MapClient, Segmenter, CameraPublisher.";
  m.attr("__version__") = semfuse::client::version();

  // The client library logs with spdlog on stderr, at $SEMFUSE_LOG_LEVEL or info.
  if (semfuse::Status logging = semfuse::setupLogging("semfuse-python"); !logging) spdlog::warn("{}", logging.error());
  m.def(
      "set_log_level",
      [](const std::string& level) {
        auto parsed = semfuse::parseLogLevel(level);
        if (!parsed) throw py::value_error(parsed.error());
        spdlog::set_level(parsed.value());
      },
      py::arg("level"),
      "Level of the client library's log on stderr: trace, debug, info, warn, error, critical or off.");
  m.def("_stop_all_threads", &stopAllThreads,
        "Stops every Segmenter and pose subscription still running (the package runs it at exit).");

  bindParticipant(m);
  bindTypes(m);
  bindMapClient(m);
  bindSegmenter(m);
  bindCameraPublisher(m);
}
