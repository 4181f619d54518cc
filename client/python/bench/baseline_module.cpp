// _semfuse_bench: the C++ baselines bench_python.py measures the Python package against, in the
// same process and with the same participant settings: a client::Segmenter with a C++ labelling
// function, and a client::MapClient's raycast timed in C++. Built beside the package in the build
// tree, never installed.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "semfuse/client/map_client.hpp"
#include "semfuse/client/segmenter.hpp"
#include "semfuse/dds/participant.hpp"

namespace py = pybind11;
using namespace semfuse;

namespace {

// The labelling functions both languages run. "constant": one label image made once and returned
// for every frame (the cost of the call alone; the Segmenter encodes it before the next call);
// "near_far": 1 nearer than 1.5 m, 2 beyond, 0 without depth, made for each frame.
Result<Segmentation> constant(const Frame& frame) {
  static const cv::Mat labels(frame.depth.size(), CV_16UC1, cv::Scalar(1));
  Segmentation out;
  out.labels = labels;
  return out;
}

Result<Segmentation> nearAndFar(const Frame& frame) {
  Segmentation out;
  out.labels = cv::Mat(frame.depth.size(), CV_16UC1, cv::Scalar(2));
  out.labels.setTo(1, frame.depth < 1.5F);
  out.labels.setTo(0, frame.depth <= 0.0F);
  return out;
}

class CppSegmenter {
 public:
  CppSegmenter(int domain, const std::string& function) : participant_(static_cast<dds_domainid_t>(domain)) {
    client::SegmenterOptions options;
    options.segmenter_id = "bench-cpp-" + function;
    if (function != "constant" && function != "near_far") throw py::value_error("function: constant or near_far");
    segmenter_ =
        std::make_unique<client::Segmenter>(participant_, function == "constant" ? constant : nearAndFar, options);
  }
  void start() { segmenter_->start(); }
  void stop() {
    py::gil_scoped_release release;
    segmenter_->stop();
  }
  py::dict stats() const {
    const auto s = segmenter_->stats();
    py::dict out;
    out["received"] = s.received;
    out["segmented"] = s.segmented;
    out["published"] = s.published;
    out["failed"] = s.failed;
    out["last_segment_ms"] = s.last_segment_ms;
    return out;
  }

 private:
  dds::Participant participant_;
  std::unique_ptr<client::Segmenter> segmenter_;
};

class CppMapClient {
 public:
  explicit CppMapClient(int domain) : participant_(static_cast<dds_domainid_t>(domain)), client_(participant_) {}
  // Milliseconds of one raycast of every layer, as a C++ caller sees it.
  double raycastMs(const py::array_t<double, py::array::c_style | py::array::forcecast>& pose, int width, int height,
                   double fx, double fy, double cx, double cy) {
    Pose camera_to_world = Pose::Identity();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) camera_to_world.matrix()(r, c) = pose.at(r, c);
    const PinholeIntrinsics intrinsics{width, height, fx, fy, cx, cy};
    py::gil_scoped_release release;
    const auto started = std::chrono::steady_clock::now();
    auto view = client_.raycast(camera_to_world, intrinsics, client::kAllLayers, std::chrono::seconds(10));
    const auto ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    if (!view) throw std::runtime_error(view.error());
    return ms;
  }

 private:
  dds::Participant participant_;
  client::MapClient client_;
};

}  // namespace

PYBIND11_MODULE(_semfuse_bench, m) {
  m.doc() = "C++ baselines of bench_python.py (not installed).";
  py::class_<CppSegmenter>(m, "CppSegmenter")
      .def(py::init<int, const std::string&>(), py::arg("domain_id"), py::arg("function"))
      .def("start", &CppSegmenter::start)
      .def("stop", &CppSegmenter::stop)
      .def("stats", &CppSegmenter::stats);
  py::class_<CppMapClient>(m, "CppMapClient")
      .def(py::init<int>(), py::arg("domain_id"))
      .def("raycast_ms", &CppMapClient::raycastMs, py::arg("pose"), py::arg("width"), py::arg("height"), py::arg("fx"),
           py::arg("fy"), py::arg("cx"), py::arg("cy"));
}
