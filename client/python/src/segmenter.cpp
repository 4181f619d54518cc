// semfuse.Segmenter: the client library's Segmenter with a Python function. The function runs
// on the Segmenter's worker thread, which takes the interpreter's lock only for the call; the
// frame reaches it as numpy arrays sharing the decoded images' buffers, and what it returns is
// checked and copied before the lock is given back. A function that raises or returns something
// that is not a segmentation of the frame costs that frame only: it is logged and counted.
#include <pybind11/stl.h>

#include <atomic>
#include <mutex>
#include <thread>

#include <spdlog/spdlog.h>

#include "arrays.hpp"
#include "runtime.hpp"
#include "semfuse/client/segmenter.hpp"

namespace semfuse::python {
namespace {

// A frame as the Python function sees it.
struct PyFrame {
  std::string camera_id;
  uint64_t seq = 0;
  double stamp = 0.0;
  std::string frame_id;
  PinholeIntrinsics intrinsics;
  py::object color;  // (H, W, 3) uint8 RGB, or None
  py::object depth;  // (H, W) float32 metres, 0 = no depth
  py::object pose;   // 4x4 camera-to-world, or None
};

PyFrame toPython(const Frame& frame) {
  PyFrame out;
  out.camera_id = frame.camera_id;
  out.seq = frame.seq;
  out.stamp = frame.stamp.seconds();
  out.frame_id = frame.frame_id;
  out.intrinsics = frame.intrinsics;
  out.color = imageToArray(frame.color);
  out.depth = imageToArray(frame.depth);
  out.pose = frame.camera_to_world ? py::object(poseToArray(*frame.camera_to_world)) : py::none();
  return out;
}

// What the function returned, as a segmentation of `frame`, or why it is not one.
Result<Segmentation> segmentationOf(const py::object& result, const Frame& frame) {
  static const std::string kReturn = "return labels, (labels, confidence) or (labels, confidence, instances)";
  py::object labels = result;
  py::object confidence = py::none();
  py::object instances = py::none();
  if (py::isinstance<py::tuple>(result) || py::isinstance<py::list>(result)) {
    const auto parts = py::reinterpret_borrow<py::sequence>(result);
    if (parts.size() != 2 && parts.size() != 3)
      return makeError(ErrorCode::kInvalidArgument,
                       "the callback returned a sequence of " + std::to_string(parts.size()) + " items; " + kReturn);
    labels = parts[0];
    confidence = parts[1];
    if (parts.size() == 3) instances = parts[2];
  } else if (result.is_none()) {
    return makeError(ErrorCode::kInvalidArgument, "the callback returned None; " + kReturn);
  }
  auto label_image = labelsFromArray(labels);
  if (!label_image) return label_image.errorInfo();
  Segmentation out;
  out.labels = std::move(label_image).value();
  if (out.labels.cols > frame.depth.cols || out.labels.rows > frame.depth.rows)
    return makeError(ErrorCode::kInvalidArgument,
                     "labels of " + std::to_string(out.labels.rows) + "x" + std::to_string(out.labels.cols) +
                         " (rows x cols) are larger than the frame's " + std::to_string(frame.depth.rows) + "x" +
                         std::to_string(frame.depth.cols));
  if (!confidence.is_none()) {
    auto confidence_image = confidenceFromArray(confidence, out.labels.size());
    if (!confidence_image) return confidence_image.errorInfo();
    out.confidence = std::move(confidence_image).value();
  }
  if (!instances.is_none()) {
    auto instance_image = instancesFromArray(instances, out.labels.size());
    if (!instance_image) return instance_image.errorInfo();
    out.instances = std::move(instance_image).value();
  }
  return out;
}

// What the worker thread shares with the Python object: the function and its own counts.
struct CallbackState {
  explicit CallbackState(py::function f) : callback(std::move(f)) {}
  PyObjectHolder callback;
  std::string where;
  std::atomic<uint64_t> callback_errors{0};
  std::atomic<uint64_t> invalid_results{0};
  std::atomic<std::thread::id> worker{};
  std::mutex mutex;
  std::string last_error;

  void remember(const std::string& error) {
    std::lock_guard lock(mutex);
    last_error = error;
  }
};

client::SegmentFunction segmentFunction(std::shared_ptr<CallbackState> state) {
  // Nothing may leave this function but a Result: an exception would end the worker thread, and
  // with it the process.
  return [state = std::move(state)](const Frame& frame) -> Result<Segmentation> {
    py::gil_scoped_acquire gil;
    state->worker = std::this_thread::get_id();
    py::object result;
    try {
      result = state->callback.object(toPython(frame));
    } catch (py::error_already_set& e) {
      const std::string line = describeCallbackError(e, state->callback_errors, state->where);
      ++state->callback_errors;
      state->remember(line);
      return makeError(ErrorCode::kInvalidArgument, "the callback raised " + line);
    } catch (const std::exception& e) {  // the frame could not be handed over
      state->remember(e.what());
      return makeError(ErrorCode::kInternal, std::string("the frame could not be given to Python: ") + e.what());
    }
    try {
      auto segmentation = segmentationOf(result, frame);
      if (!segmentation) {
        ++state->invalid_results;
        state->remember(segmentation.error());
      }
      return segmentation;
    } catch (py::error_already_set& e) {  // reading the result ran Python code that raised
      ++state->invalid_results;
      const std::string line = py::str(e.value()).cast<std::string>();
      state->remember(line);
      return makeError(ErrorCode::kInvalidArgument, "the callback's result: " + line);
    } catch (const std::exception& e) {
      ++state->invalid_results;
      state->remember(e.what());
      return makeError(ErrorCode::kInvalidArgument, std::string("the callback's result: ") + e.what());
    }
  };
}

struct SegmenterStats {
  client::SegmenterStats counts;
  uint64_t callback_errors = 0;
  uint64_t invalid_results = 0;
  std::string last_error;
};

class Segmenter : public ThreadOwner {
 public:
  Segmenter(py::function callback, const std::string& segmenter_id, const std::string& camera_id, int every,
            double delay_s, const py::object& participant, std::optional<int> domain)
      : participant_(participantFor(participant, domain)),
        state_(std::make_shared<CallbackState>(std::move(callback))) {
    if (every < 1) throw py::value_error("every must be >= 1");
    client::SegmenterOptions options;
    options.segmenter_id = segmenter_id;
    options.camera_id = camera_id;
    options.every = every;
    options.delay = toTimeout(delay_s, std::chrono::milliseconds(0));
    state_->where = "segmenter '" + segmenter_id + "'";
    py::gil_scoped_release release;
    segmenter_ = std::make_unique<client::Segmenter>(*participant_, segmentFunction(state_), options);
  }

  ~Segmenter() override {
    py::gil_scoped_release release;  // the worker may be waiting for the interpreter's lock
    segmenter_.reset();              // stops the threads, then deletes the DDS entities
  }

  void start() {
    py::gil_scoped_release release;
    segmenter_->start();
    running_ = true;
  }

  void stop() {
    if (state_->worker.load() == std::this_thread::get_id())
      throw std::runtime_error("stop() from inside the segmenter's callback would wait for itself");
    py::gil_scoped_release release;
    if (segmenter_) segmenter_->stop();
    running_ = false;
  }
  void stopThreads() override { stop(); }

  SegmenterStats stats() const {
    SegmenterStats out;
    out.counts = segmenter_->stats();
    out.callback_errors = state_->callback_errors;
    out.invalid_results = state_->invalid_results;
    std::lock_guard lock(state_->mutex);
    out.last_error = state_->last_error;
    return out;
  }

  // Runs until `duration` seconds passed, or `idle_exit` seconds without a frame after the first,
  // or Ctrl-C; starts the segmenter first when it is not running.
  SegmenterStats run(std::optional<double> duration_s, std::optional<double> idle_exit_s) {
    if (!running_) start();
    using Clock = std::chrono::steady_clock;
    const auto started = Clock::now();
    auto last_activity = started;
    uint64_t last_received = stats().counts.received;
    for (;;) {
      {
        py::gil_scoped_release release;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      const auto now = Clock::now();
      const uint64_t received = segmenter_->stats().received;
      if (received != last_received) {
        last_received = received;
        last_activity = now;
      }
      if (duration_s && now - started >= std::chrono::duration<double>(*duration_s)) break;
      if (idle_exit_s && last_received > 0 && now - last_activity >= std::chrono::duration<double>(*idle_exit_s)) break;
    }
    return stats();
  }

  bool waitForCamera(double timeout_s) const {
    const auto t = toTimeout(timeout_s, std::chrono::milliseconds(0));
    py::gil_scoped_release release;
    return segmenter_->waitForCamera(t);
  }
  bool waitForAcknowledgements(double timeout_s) const {
    const auto t = toTimeout(timeout_s, std::chrono::milliseconds(0));
    py::gil_scoped_release release;
    return segmenter_->waitForAcknowledgements(t).ok();
  }
  bool running() const { return running_; }

 private:
  SharedParticipant participant_;  // outlives the segmenter
  std::shared_ptr<CallbackState> state_;
  std::unique_ptr<client::Segmenter> segmenter_;
  bool running_ = false;
};

}  // namespace

void bindSegmenter(py::module_& m) {
  py::class_<PyFrame>(m, "Frame", "An RGB-D frame as a segmenter callback receives it.")
      .def_readonly("camera_id", &PyFrame::camera_id)
      .def_readonly("seq", &PyFrame::seq, "The camera's sequence number of the frame.")
      .def_readonly("stamp", &PyFrame::stamp, "Time stamp, seconds.")
      .def_readonly("frame_id", &PyFrame::frame_id)
      .def_readonly("intrinsics", &PyFrame::intrinsics)
      .def_readonly("color", &PyFrame::color, "(H, W, 3) uint8 RGB (not OpenCV's BGR), or None.")
      .def_readonly("depth", &PyFrame::depth, "(H, W) float32 metres, 0 where there is no depth.")
      .def_readonly("pose", &PyFrame::pose, "4x4 float64 camera-to-world, or None when the camera sends none.")
      .def("__repr__", [](const PyFrame& f) {
        return "semfuse.Frame(camera_id='" + f.camera_id + "', seq=" + std::to_string(f.seq) + ", " +
               std::to_string(f.intrinsics.width) + "x" + std::to_string(f.intrinsics.height) + ")";
      });

  py::class_<SegmenterStats>(m, "SegmenterStats", "What a Segmenter did so far.")
      .def_property_readonly(
          "received", [](const SegmenterStats& s) { return s.counts.received; }, "Frames seen on the topic.")
      .def_property_readonly(
          "not_selected", [](const SegmenterStats& s) { return s.counts.not_selected; },
          "Frames left out by `every` (or of another camera).")
      .def_property_readonly(
          "skipped", [](const SegmenterStats& s) { return s.counts.skipped; },
          "Frames replaced by a newer one before the callback got to them.")
      .def_property_readonly(
          "segmented", [](const SegmenterStats& s) { return s.counts.segmented; },
          "Frames the callback labeled with a valid result.")
      .def_property_readonly("published", [](const SegmenterStats& s) { return s.counts.published; })
      .def_property_readonly(
          "failed", [](const SegmenterStats& s) { return s.counts.failed; },
          "Frames that failed: callback errors, invalid results, undecodable frames, write errors.")
      .def_readonly("callback_errors", &SegmenterStats::callback_errors, "Calls that raised.")
      .def_readonly("invalid_results", &SegmenterStats::invalid_results,
                    "Calls that returned something that is not a segmentation of the frame (wrong size, dtype, ...).")
      .def_readonly("last_error", &SegmenterStats::last_error, "The last callback error or invalid result, or ''.")
      .def_property_readonly(
          "mean_segment_ms", [](const SegmenterStats& s) { return s.counts.meanSegmentMs(); },
          "Mean time of a successful call, with the conversions to and from numpy.")
      .def_property_readonly("last_segment_ms", [](const SegmenterStats& s) { return s.counts.last_segment_ms; })
      .def("__repr__", [](const SegmenterStats& s) {
        return "semfuse.SegmenterStats(received=" + std::to_string(s.counts.received) +
               ", segmented=" + std::to_string(s.counts.segmented) +
               ", published=" + std::to_string(s.counts.published) + ", failed=" + std::to_string(s.counts.failed) +
               ")";
      });

  py::class_<Segmenter>(m, "Segmenter", R"doc(
Runs a Python function on the frames cameras publish and publishes its labels to the server.

    def segment(frame: semfuse.Frame):
        labels = my_network(frame.color)        # (H, W) integer label ids of the server's legend
        return labels.astype(np.uint16)          # or (labels, confidence) with float confidence in [0, 1]
                                                 # or (labels, confidence, instances): panoptic

    with semfuse.Segmenter(segment, segmenter_id="my-net", every=2) as segmenter:
        segmenter.run(idle_exit=10)

The callback runs on the segmenter's worker thread, one frame at a time, always on the newest
frame (a slow callback skips frames instead of falling behind). Labels may be smaller than the
frame (the server upsamples them); 0 is unlabeled. A callback that raises, or returns labels
that are not a 2-D integer array within uint16 and within the frame's size, costs that frame
only: it is logged and counted (``stats().callback_errors``, ``invalid_results``).
)doc")
      .def(py::init<py::function, const std::string&, const std::string&, int, double, const py::object&,
                    std::optional<int>>(),
           py::arg("callback"), py::arg("segmenter_id") = "python-segmenter", py::arg("camera_id") = "",
           py::arg("every") = 1, py::arg("delay") = 0.0, py::arg("participant") = py::none(),
           py::arg("domain_id") = py::none(), R"doc(
``segmenter_id`` is published with each result; ``camera_id`` selects one camera ('' = all);
``every`` segments every Nth frame received; ``delay`` holds each result that many seconds before
publishing it (a late model). The segmenter starts with start(), run() or ``with``.
)doc")
      .def("start", &Segmenter::start, "Starts receiving frames and calling the callback.")
      .def("stop", &Segmenter::stop, "Finishes and publishes the frame in hand, then stops.")
      .def("run", &Segmenter::run, py::arg("duration") = py::none(), py::arg("idle_exit") = py::none(), R"doc(
Blocks while the segmenter works: until ``duration`` seconds passed, or ``idle_exit`` seconds
without a frame once frames came, or Ctrl-C (KeyboardInterrupt). Starts it if needed; returns
the stats.
)doc")
      .def("stats", &Segmenter::stats, "The counts so far: frames received, segmented, published, failed and why.")
      .def_property_readonly("running", &Segmenter::running)
      .def("wait_for_camera", &Segmenter::waitForCamera, py::arg("timeout"),
           "True once a camera's frames writer is matched, waiting at most `timeout` seconds.")
      .def("wait_for_acknowledgements", &Segmenter::waitForAcknowledgements, py::arg("timeout"),
           "True once the server acknowledged every published result, waiting at most `timeout` seconds.")
      .def("__enter__",
           [](Segmenter& s) -> Segmenter& {
             s.start();
             return s;
           })
      .def("__exit__", [](Segmenter& s, const py::args&) { s.stop(); });
}

}  // namespace semfuse::python
