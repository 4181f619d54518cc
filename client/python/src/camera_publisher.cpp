// semfuse.CameraPublisher: publishes numpy RGB-D frames; encoding and writing run without the
// interpreter's lock.
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>

#include "arrays.hpp"
#include "runtime.hpp"
#include "semfuse/client/camera_publisher.hpp"
#include "semfuse/core/camera_check.hpp"

namespace semfuse::python {
namespace {

Stamp stampOf(const std::optional<double>& seconds) {
  double s = 0.0;
  if (seconds) {
    if (!std::isfinite(*seconds) || *seconds < 0.0) throw py::value_error("stamp must be seconds >= 0");
    s = *seconds;
  } else {
    s = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  }
  Stamp stamp;
  stamp.sec = static_cast<int32_t>(std::floor(s));
  stamp.nanosec = static_cast<uint32_t>(std::llround((s - std::floor(s)) * 1e9) % 1000000000);
  return stamp;
}

class CameraPublisher {
 public:
  CameraPublisher(std::string camera_id, const std::string& depth_encoding, const std::string& color_encoding,
                  int jpeg_quality, const py::object& participant, std::optional<int> domain)
      : participant_(participantFor(participant, domain)), camera_id_(std::move(camera_id)) {
    if (camera_id_.empty()) throw py::value_error("camera_id must not be empty");
    client::CameraPublisherOptions options;
    const auto depth = client::parseDepthEncoding(depth_encoding);
    if (!depth) throw py::value_error("depth_encoding must be raw, float, png or rvl, not '" + depth_encoding + "'");
    const auto color = client::parseColorEncoding(color_encoding);
    if (!color) throw py::value_error("color_encoding must be none, raw, jpeg or png, not '" + color_encoding + "'");
    if (jpeg_quality < 1 || jpeg_quality > 100) throw py::value_error("jpeg_quality must be in 1..100");
    options.depth_encoding = *depth;
    options.color_encoding = *color;
    options.jpeg_quality = jpeg_quality;
    py::gil_scoped_release release;
    publisher_ = std::make_unique<client::CameraPublisher>(*participant_, options);
  }

  ~CameraPublisher() {
    py::gil_scoped_release release;
    publisher_.reset();
  }

  uint64_t publish(const py::handle& depth, const PinholeIntrinsics& intrinsics, const py::object& color,
                   const py::object& pose, std::optional<uint64_t> seq, std::optional<double> stamp,
                   const std::string& frame_id) {
    Frame frame;
    frame.camera_id = camera_id_;
    frame.seq = seq.value_or(next_seq_);
    frame.stamp = stampOf(stamp);
    frame.frame_id = frame_id;
    frame.intrinsics = intrinsics;
    if (Status ok = checkIntrinsics(intrinsics, static_cast<int>(kMaxImageSide)); !ok)
      throw py::value_error(ok.error());
    frame.depth = depthFromArray(depth, "depth");
    if (frame.depth.cols != intrinsics.width || frame.depth.rows != intrinsics.height)
      throw py::value_error("depth is " + std::to_string(frame.depth.rows) + "x" + std::to_string(frame.depth.cols) +
                            " (rows x cols), the intrinsics say " + std::to_string(intrinsics.height) + "x" +
                            std::to_string(intrinsics.width));
    if (!color.is_none()) {
      frame.color = colorFromArray(color, "color");
      if (frame.color.size() != frame.depth.size())
        throw py::value_error("color is " + std::to_string(frame.color.rows) + "x" + std::to_string(frame.color.cols) +
                              ", depth " + std::to_string(frame.depth.rows) + "x" + std::to_string(frame.depth.cols));
    }
    if (!pose.is_none()) frame.camera_to_world = poseFromArray(pose, "pose");
    Status sent;
    {
      py::gil_scoped_release release;  // the arrays stay alive: the caller holds them
      sent = publisher_->publish(frame);
    }
    if (!sent) raiseError(sent.errorInfo().prefixed("frame " + std::to_string(frame.seq) + ": "));
    next_seq_ = frame.seq + 1;
    return frame.seq;
  }

  bool waitForServer(double timeout_s) const {
    const auto t = toTimeout(timeout_s, std::chrono::milliseconds(0));
    py::gil_scoped_release release;
    return publisher_->waitForServer(t);
  }
  bool waitForReader(double timeout_s) const {
    const auto t = toTimeout(timeout_s, std::chrono::milliseconds(0));
    py::gil_scoped_release release;
    return publisher_->waitForReader(t);
  }
  bool waitForAcknowledgements(double timeout_s) const {
    const auto t = toTimeout(timeout_s, std::chrono::milliseconds(0));
    py::gil_scoped_release release;
    return publisher_->waitForAcknowledgements(t).ok();
  }
  int matchedReaders() const { return publisher_->matchedReaders(); }
  std::size_t lastPayloadBytes() const { return publisher_->lastPayloadBytes(); }
  const std::string& cameraId() const { return camera_id_; }
  uint64_t nextSeq() const { return next_seq_; }

 private:
  SharedParticipant participant_;  // outlives the publisher
  std::string camera_id_;
  std::unique_ptr<client::CameraPublisher> publisher_;
  uint64_t next_seq_ = 0;
};

}  // namespace

void bindCameraPublisher(py::module_& m) {
  py::class_<CameraPublisher>(m, "CameraPublisher", R"doc(
Publishes RGB-D frames for the server to fuse (and segmenters to label).

    camera = semfuse.CameraPublisher("kitchen")
    camera.wait_for_server(10)       # a reliable writer keeps nothing for readers not yet discovered
    camera.publish(depth, intrinsics, color=rgb, pose=camera_to_world)
    camera.wait_for_acknowledgements(5)

Without a pose the server tracks the camera against the map.
)doc")
      .def(py::init<std::string, const std::string&, const std::string&, int, const py::object&, std::optional<int>>(),
           py::arg("camera_id") = "python", py::arg("depth_encoding") = "raw", py::arg("color_encoding") = "jpeg",
           py::arg("jpeg_quality") = 90, py::arg("participant") = py::none(), py::arg("domain_id") = py::none(),
           "Encodings on the wire: depth raw (16-bit mm), float (32-bit m), png or rvl (both lossless 16-bit mm, rvl "
           "the cheaper for the server to decode); colour none, raw, jpeg or png.")
      .def("publish", &CameraPublisher::publish, py::arg("depth"), py::arg("intrinsics"), py::arg("color") = py::none(),
           py::arg("pose") = py::none(), py::arg("seq") = py::none(), py::arg("stamp") = py::none(),
           py::arg("frame_id") = "", R"doc(
Encodes and writes one frame; returns its sequence number (by default one more than the last).
``depth``: (H, W) float metres or uint16 millimetres, 0 = no depth, of the intrinsics' size;
``color``: (H, W, 3) uint8 RGB or None; ``pose``: 4x4 camera-to-world or None; ``stamp``: seconds
(default: now). Raises ValueError for malformed arrays and semfuse.Error when the frame cannot be
encoded or the server does not take it within 2 s.
)doc")
      .def("wait_for_server", &CameraPublisher::waitForServer, py::arg("timeout"),
           "True once a semfuse server reads the frames, waiting at most `timeout` seconds.")
      .def("wait_for_reader", &CameraPublisher::waitForReader, py::arg("timeout"),
           "True once any frames reader (a server, a segmenter) is matched.")
      .def("wait_for_acknowledgements", &CameraPublisher::waitForAcknowledgements, py::arg("timeout"),
           "True once every matched reader acknowledged every frame, waiting at most `timeout` seconds.")
      .def_property_readonly("matched_readers", &CameraPublisher::matchedReaders)
      .def_property_readonly("last_payload_bytes", &CameraPublisher::lastPayloadBytes,
                             "Bytes of the last frame's depth and colour payloads.")
      .def_property_readonly("camera_id", &CameraPublisher::cameraId)
      .def_property_readonly("next_seq", &CameraPublisher::nextSeq);
}

}  // namespace semfuse::python
