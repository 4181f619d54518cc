// semfuse.MapClient: every query of the map (the distance field's among them, as dicts of arrays
// from distance_arrays.hpp) as a blocking call that releases the interpreter's lock while it
// waits, with results as numpy arrays; the server's poses as an iterator or a
// callback (pose_subscription.cpp).
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <deque>

#include "arrays.hpp"
#include "distance_arrays.hpp"
#include "pose_subscription.hpp"
#include "python_types.hpp"
#include "runtime.hpp"

namespace semfuse::python {
namespace {

using Timeout = client::Timeout;

struct LayerName {
  const char* name;
  client::RaycastLayer bit;
};
constexpr LayerName kLayerNames[] = {{"depth", client::kDepthLayer},
                                     {"normals", client::kNormalsLayer},
                                     {"labels", client::kLabelsLayer},
                                     {"confidence", client::kConfidenceLayer},
                                     {"color", client::kColorLayer}};

client::RaycastLayers layerOf(const std::string& name) {
  for (const auto& layer : kLayerNames)
    if (name == layer.name) return layer.bit;
  throw py::value_error("unknown raycast layer '" + name + "' (depth, normals, labels, confidence, color)");
}

// None: all; an int: the bits (DEPTH | LABELS); a name or names: those layers.
client::RaycastLayers parseLayers(const py::object& layers) {
  if (layers.is_none()) return client::kAllLayers;
  if (py::isinstance<py::int_>(layers)) {
    const auto bits = layers.cast<long long>();
    if (bits <= 0 || bits > static_cast<long long>(client::kAllLayers))
      throw py::value_error("layers: bits of DEPTH, NORMALS, LABELS, CONFIDENCE, COLOR, got " + std::to_string(bits));
    return static_cast<client::RaycastLayers>(bits);
  }
  if (py::isinstance<py::str>(layers)) return layerOf(layers.cast<std::string>());
  client::RaycastLayers bits = 0;
  for (const auto& name : layers) bits |= layerOf(py::str(name).cast<std::string>());
  if (bits == 0) throw py::value_error("layers: no layer named");
  return bits;
}

py::dict raycastDict(const client::RaycastImages& images) {
  py::dict out;
  const std::pair<const char*, const cv::Mat*> layers[] = {{"depth", &images.depth},
                                                           {"normals", &images.normals},
                                                           {"labels", &images.labels},
                                                           {"confidence", &images.confidence},
                                                           {"color", &images.color}};
  for (const auto& [name, image] : layers)
    if (!image->empty()) out[name] = imageToArray(*image);
  return out;
}

py::dict samplesDict(const std::vector<client::VoxelSample>& samples) {
  const auto n = static_cast<py::ssize_t>(samples.size());
  py::array_t<bool> observed(n);
  py::array_t<uint16_t> label(n);
  py::array_t<float> confidence(n), tsdf(n), weight(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    observed.mutable_at(i) = samples[i].observed;
    label.mutable_at(i) = samples[i].label;
    confidence.mutable_at(i) = samples[i].confidence;
    tsdf.mutable_at(i) = samples[i].tsdf;
    weight.mutable_at(i) = samples[i].weight;
  }
  py::dict out;
  out["observed"] = observed;
  out["label"] = label;
  out["confidence"] = confidence;
  out["tsdf"] = tsdf;
  out["weight"] = weight;
  return out;
}

client::Box boxOf(const py::handle& box_min, const py::handle& box_max) {
  client::Box box{pointFromArray(box_min, "box_min"), pointFromArray(box_max, "box_max")};
  return box;
}

// Iterates over the server's poses as they come, until `idle` seconds pass without one.
class PoseIterator {
 public:
  PoseIterator(std::shared_ptr<PoseSource> source, std::optional<double> idle_s)
      : source_(std::move(source)), idle_s_(idle_s) {}

  TrackedPose next() {
    using Clock = std::chrono::steady_clock;
    const auto started = Clock::now();
    while (buffered_.empty()) {
      source_->checkNotSubscribed();
      // Slices of 100 ms, so that Ctrl-C (which Python sees only between them) ends a long wait.
      auto slice = std::chrono::milliseconds(100);
      if (idle_s_) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            std::chrono::duration<double>(*idle_s_) - (Clock::now() - started));
        if (left.count() <= 0) throw py::stop_iteration();
        slice = std::min(slice, left);
      }
      std::vector<TrackedPose> poses;
      {
        py::gil_scoped_release release;
        poses = source_->client->takePoses(slice);
      }
      buffered_.insert(buffered_.end(), std::make_move_iterator(poses.begin()), std::make_move_iterator(poses.end()));
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    TrackedPose pose = std::move(buffered_.front());
    buffered_.pop_front();
    return pose;
  }

 private:
  std::shared_ptr<PoseSource> source_;
  std::optional<double> idle_s_;
  std::deque<TrackedPose> buffered_;
};

class MapClient {
 public:
  MapClient(const py::object& participant, std::optional<int> domain, double timeout_s)
      : participant_(participantFor(participant, domain)),
        timeout_(toTimeout(timeout_s, Timeout(0))),
        source_(std::make_shared<PoseSource>()) {
    py::gil_scoped_release release;
    source_->client = std::make_shared<client::MapClient>(*participant_);
    source_->participant = participant_;
  }

  Timeout timeoutOr(const std::optional<double>& seconds) const { return toTimeout(seconds, timeout_); }
  client::MapClient& client() { return *source_->client; }

  // Runs `call` on the client without the interpreter's lock and returns its value or raises.
  template <class F>
  auto run(F&& call) {
    auto result = [&] {
      py::gil_scoped_release release;
      return call(client());
    }();
    return valueOrRaise(std::move(result));
  }

  py::dict raycast(const py::handle& pose, const PinholeIntrinsics& intrinsics, const py::object& layers,
                   float max_range, const std::optional<double>& timeout) {
    const Pose camera_to_world = poseFromArray(pose, "pose");
    const auto bits = parseLayers(layers);
    const auto t = timeoutOr(timeout);
    return raycastDict(
        run([&](client::MapClient& c) { return c.raycast(camera_to_world, intrinsics, bits, t, max_range); }));
  }

  py::dict labelsAt(const py::handle& points, const std::optional<double>& timeout) {
    const auto p = pointsFromArray(points, "points");
    const auto t = timeoutOr(timeout);
    return samplesDict(run([&](client::MapClient& c) { return c.labelsAt(p, t); }));
  }

  client::RegionSummary region(const py::handle& box_min, const py::handle& box_max,
                               const std::optional<double>& timeout) {
    const auto box = boxOf(box_min, box_max);
    const auto t = timeoutOr(timeout);
    return run([&](client::MapClient& c) { return c.region(box, t); });
  }

  std::vector<client::ObjectInstance> objects(LabelId label, uint32_t min_voxels, const py::object& near, double radius,
                                              bool include_fragments, double max_age,
                                              const std::optional<double>& timeout) {
    if (!(max_age >= 0.0) || !std::isfinite(max_age)) throw py::value_error("max_age must be 0 or more seconds");
    client::ObjectsRequest request;
    request.max_age_s = max_age;
    request.label = label;
    request.min_voxels = min_voxels;
    request.include_fragments = include_fragments;
    if (!near.is_none()) {
      if (!(radius > 0.0) || !std::isfinite(radius)) throw py::value_error("radius must be positive with near");
      request.near = pointFromArray(near, "near");
      request.radius = radius;
    }
    const auto t = timeoutOr(timeout);
    return run([&](client::MapClient& c) { return c.objects(request, t); });
  }

  Mesh mesh(const py::object& box_min, const py::object& box_max, const std::optional<double>& timeout) {
    if (box_min.is_none() != box_max.is_none()) throw py::value_error("give both box_min and box_max, or neither");
    std::optional<client::Box> box;
    if (!box_min.is_none()) box = boxOf(box_min, box_max);
    const auto t = timeoutOr(timeout);
    return meshFromPly(std::move(run([&](client::MapClient& c) { return c.mesh(box, t); }).ply));
  }

  // The distance field (servers started with --esdf).
  py::dict distances(const py::handle& points, const std::optional<double>& timeout) {
    const auto p = pointsFromArray(points, "points");
    const auto t = timeoutOr(timeout);
    return distanceSamplesDict(run([&](client::MapClient& c) { return c.distances(p, t); }));
  }
  py::dict occupancySlice(double z_min, double z_max, const py::object& bounds_min, const py::object& bounds_max,
                          double inflation_radius, const std::optional<double>& timeout) {
    if (bounds_min.is_none() != bounds_max.is_none())
      throw py::value_error("give both bounds_min and bounds_max, or neither");
    client::OccupancySliceRequest request;
    request.z_min = z_min;
    request.z_max = z_max;
    request.inflation_radius = inflation_radius;
    if (!bounds_min.is_none()) {
      request.use_bounds = true;
      request.min = planePointFromArray(bounds_min, "bounds_min");
      request.max = planePointFromArray(bounds_max, "bounds_max");
    }
    const auto t = timeoutOr(timeout);
    return occupancyGridDict(run([&](client::MapClient& c) { return c.occupancySlice(request, t); }));
  }
  py::dict semanticDistances(const std::vector<LabelId>& labels, const py::handle& points,
                             const std::optional<double>& timeout) {
    const auto p = pointsFromArray(points, "points");
    const auto t = timeoutOr(timeout);
    return semanticSamplesDict(run([&](client::MapClient& c) { return c.semanticDistances(labels, p, t); }));
  }
  py::dict semanticSlice(const std::vector<LabelId>& labels, double z, const py::handle& bounds_min,
                         const py::handle& bounds_max, double resolution, const std::optional<double>& timeout) {
    client::SemanticSliceRequest request;
    request.labels = labels;
    request.z = z;
    request.min = planePointFromArray(bounds_min, "bounds_min");
    request.max = planePointFromArray(bounds_max, "bounds_max");
    request.resolution = resolution;
    const auto t = timeoutOr(timeout);
    return semanticSliceDict(run([&](client::MapClient& c) { return c.semanticSlice(request, t); }));
  }
  py::dict checkSegments(const py::handle& starts, const py::handle& ends, double radius,
                         const std::optional<double>& timeout) {
    const auto segments = segmentsFromArrays(starts, ends);
    const auto t = timeoutOr(timeout);
    return segmentResultsDict(run([&](client::MapClient& c) { return c.checkSegments(segments, radius, t); }));
  }

  ServerStatus status(const std::optional<double>& timeout) {
    const auto t = timeoutOr(timeout);
    return run([&](client::MapClient& c) { return c.stats(t); });
  }
  ServerStatus save(const std::string& path, const std::optional<double>& timeout) {
    const auto t = timeoutOr(timeout);
    return run([&](client::MapClient& c) { return c.save(path, t); });
  }
  ServerStatus load(const std::string& path, const std::optional<double>& timeout) {
    const auto t = timeoutOr(timeout);
    return run([&](client::MapClient& c) { return c.load(path, t); });
  }
  ServerStatus reset(const std::optional<double>& timeout) {
    const auto t = timeoutOr(timeout);
    return run([&](client::MapClient& c) { return c.reset(t); });
  }

  std::optional<ServerStatus> latestStatus() {
    py::gil_scoped_release release;
    return client().latestStatus();
  }
  std::optional<LabelLegend> latestLegend() {
    py::gil_scoped_release release;
    return client().latestLegend();
  }
  ServerStatus waitForStatus(const std::optional<double>& timeout) {
    const auto t = timeoutOr(timeout);
    std::optional<ServerStatus> status;
    {
      py::gil_scoped_release release;
      status = client().waitForStatus(t);
    }
    if (!status)
      raiseCallFailure(client::Failure::kTimeout, "no server status within the timeout", ErrorCode::kUnavailable);
    return std::move(*status);
  }
  LabelLegend legend(const std::optional<double>& timeout) {
    const auto t = timeoutOr(timeout);
    std::optional<LabelLegend> legend;
    {
      py::gil_scoped_release release;
      legend = client().waitForLegend(t);
    }
    if (!legend)
      raiseCallFailure(client::Failure::kTimeout, "no label legend within the timeout", ErrorCode::kUnavailable);
    return std::move(*legend);
  }

  std::vector<TrackedPose> takePoses(double timeout_s) {
    source_->checkNotSubscribed();
    const auto t = toTimeout(timeout_s, Timeout(0));
    py::gil_scoped_release release;
    return client().takePoses(t);
  }
  PoseIterator poses(std::optional<double> idle_s) {
    if (idle_s) toTimeout(idle_s, Timeout(0));  // checks it
    source_->checkNotSubscribed();
    return PoseIterator(source_, idle_s);
  }
  std::unique_ptr<PoseSubscription> subscribePoses(py::function callback) {
    return std::make_unique<PoseSubscription>(source_, std::move(callback));
  }
  uint64_t rejectedPoses() const { return source_->client->rejectedPoses(); }
  std::vector<ObjectEvents> takeObjectEvents(double timeout_s) {
    const auto t = toTimeout(timeout_s, Timeout(0));
    py::gil_scoped_release release;
    return client().takeObjectEvents(t);
  }
  uint64_t rejectedObjectEvents() const { return source_->client->rejectedObjectEvents(); }
  double timeoutSeconds() const { return timeout_.count() / 1000.0; }
  int domain() const { return static_cast<int>(participant_->domain()); }

 private:
  SharedParticipant participant_;
  Timeout timeout_;
  std::shared_ptr<PoseSource> source_;
};

}  // namespace

void bindMapClient(py::module_& m) {
  m.attr("DEPTH") = static_cast<uint32_t>(client::kDepthLayer);
  m.attr("NORMALS") = static_cast<uint32_t>(client::kNormalsLayer);
  m.attr("LABELS") = static_cast<uint32_t>(client::kLabelsLayer);
  m.attr("CONFIDENCE") = static_cast<uint32_t>(client::kConfidenceLayer);
  m.attr("COLOR") = static_cast<uint32_t>(client::kColorLayer);
  m.attr("ALL_LAYERS") = static_cast<uint32_t>(client::kAllLayers);

  py::class_<PoseIterator>(m, "PoseIterator", "The server's poses as they arrive (MapClient.poses()).")
      .def("__iter__", [](PoseIterator& it) -> PoseIterator& { return it; })
      .def("__next__", &PoseIterator::next);

  bindPoseSubscription(m);

  py::class_<MapClient>(m, "MapClient", R"doc(
Queries the semfuse map server. Every query blocks until the reply comes or its timeout passes,
with the interpreter's lock released, and raises on failure: ``CallTimeout`` (also a
``TimeoutError``) when no server answers in time, ``ServerError`` with the server's message and
``reason`` when it refuses, ``ClientError`` when its reply cannot be read.

Poses are 4x4 camera-to-world matrices (x right, y down, z forward), lengths in metres.
)doc")
      .def(py::init<const py::object&, std::optional<int>, double>(), py::arg("participant") = py::none(),
           py::arg("domain_id") = py::none(), py::arg("timeout") = 10.0,
           "Connects to the server on DDS domain ``domain_id`` (or through ``participant``). ``timeout`` is the "
           "default of every call, seconds.")
      .def_property_readonly("timeout", &MapClient::timeoutSeconds, "The default timeout of a call, seconds.")
      .def_property_readonly("domain_id", &MapClient::domain)
      .def("raycast", &MapClient::raycast, py::arg("pose"), py::arg("intrinsics"), py::arg("layers") = py::none(),
           py::arg("max_range") = 0.0F, py::arg("timeout") = py::none(), R"doc(
Renders the map from a camera. ``layers``: None (all), bits (``DEPTH | LABELS``) or names
(``["depth", "labels"]``). Returns a dict with the layers asked for:
``depth`` (H, W) float32 metres along z (0: no surface), ``normals`` (H, W, 3) float32 world frame,
``labels`` (H, W) uint16 (0: unlabeled), ``confidence`` (H, W) float32 label score,
``color`` (H, W, 3) uint8 RGB. ``max_range`` metres, 0: the server's default.
)doc")
      .def("labels_at", &MapClient::labelsAt, py::arg("points"), py::arg("timeout") = py::none(), R"doc(
The voxels at (N, 3) world points: a dict of (N,) arrays ``observed`` (bool), ``label`` (uint16),
``confidence``, ``tsdf`` (metres) and ``weight`` (float32).
)doc")
      .def("region", &MapClient::region, py::arg("box_min"), py::arg("box_max"), py::arg("timeout") = py::none(),
           "Label surface areas and occupancy inside the box [box_min, box_max] (world frame, metres).")
      .def("objects", &MapClient::objects, py::arg("label") = 0, py::arg("min_voxels") = 0,
           py::arg("near") = py::none(), py::arg("radius") = 0.0, py::arg("include_fragments") = false,
           py::arg("max_age") = 0.0, py::arg("timeout") = py::none(), R"doc(
Connected labeled surfaces of `label` (0: of every label) with at least `min_voxels` voxels; with
`near` (a world point) only those whose surface comes within `radius` metres of it; with
`include_fragments` also the pieces too small to be objects. With `max_age` (seconds) the objects
the server keeps up to date in the background will do when grouped from a map at most that much
older: an answer at once while the map grows.
)doc")
      .def("mesh", &MapClient::mesh, py::arg("box_min") = py::none(), py::arg("box_max") = py::none(),
           py::arg("timeout") = py::none(),
           "The labeled mesh of the map (or of the box): arrays and the PLY. The timeout applies to each chunk.")
      .def("distances", &MapClient::distances, py::arg("points"), py::arg("timeout") = py::none(), R"doc(
Signed distance to the nearest obstacle and its unit gradient at (N, 3) world points, from the
server's distance field (servers started with ``--esdf``; others raise ``ServerError``). Returns a
dict of arrays: ``known`` (N,) bool (False: nobody observed the point; the rest means nothing),
``beyond`` (N,) bool (no surface within the field's maximum distance, which ``distance`` then
holds), ``distance`` (N,) float32 metres, negative inside obstacles, ``gradient`` (N, 3) float32,
pointing away from the nearest surface in free space.)doc")
      .def("occupancy_slice", &MapClient::occupancySlice, py::arg("z_min") = 0.1, py::arg("z_max") = 1.0,
           py::arg("bounds_min") = py::none(), py::arg("bounds_max") = py::none(), py::arg("inflation_radius") = 0.0,
           py::arg("timeout") = py::none(), R"doc(
A 2D occupancy grid of the height band [z_min, z_max] (world z up), as nav_msgs/OccupancyGrid
holds it, over the whole observed extent or the x, y box ``bounds_min`` .. ``bounds_max``. Returns
a dict: ``cells`` (H, W) int8 (0 free, 99 free within ``inflation_radius`` of an obstacle, 100
occupied, -1 unknown; row 0 at the lowest y), ``resolution`` metres per cell, ``origin`` (2,) the
x, y of cell (0, 0)'s minimum corner, ``z`` the band's middle, ``frame_id``.)doc")
      .def("semantic_distances", &MapClient::semanticDistances, py::arg("labels"), py::arg("points"),
           py::arg("timeout") = py::none(), R"doc(
Distance and direction from (N, 3) world points to the nearest surface of any of ``labels``.
Returns a dict of arrays: ``found`` (N,) bool (False: the map holds no surface of those labels),
``label`` (N,) uint16, ``distance`` (N,) float32 metres, ``direction`` (N, 3) float32 unit vector
towards ``surface_point`` (N, 3) float64.)doc")
      .def("semantic_slice", &MapClient::semanticSlice, py::arg("labels"), py::arg("z"), py::arg("bounds_min"),
           py::arg("bounds_max"), py::arg("resolution") = 0.05, py::arg("timeout") = py::none(), R"doc(
The distance to the nearest surface of any of ``labels`` over the horizontal plane at height ``z``,
in the x, y box ``bounds_min`` .. ``bounds_max``. Returns a dict: ``distance`` (H, W) float32 metres
(+inf where the map holds no surface of those labels; row 0 at ``min``'s y), ``min`` (2,),
``resolution``, ``z``.)doc")
      .def("check_segments", &MapClient::checkSegments, py::arg("starts"), py::arg("ends"), py::arg("radius") = 0.0,
           py::arg("timeout") = py::none(), R"doc(
Whether a sphere of ``radius`` metres (0: a point) moved along each segment ``starts[i]`` ..
``ends[i]`` ((N, 3) world points) stays clear. Returns a dict of arrays: ``status`` (N,) uint8 (0
free, 1 collision, 2 enters unknown space), ``fraction`` (N,) float32 where along the segment it
first failed (1 when free), ``blocked_at`` (N, 3) float64, ``min_clearance`` (N,) float32 metres
between the sphere and the nearest surface along the way.)doc")
      .def("status", &MapClient::status, py::arg("timeout") = py::none(),
           "Asks the server for its status now (the admin service).")
      .def("latest_status", &MapClient::latestStatus,
           "The newest status the server published, or None before the first one.")
      .def("wait_for_status", &MapClient::waitForStatus, py::arg("timeout") = py::none(),
           "The newest published status, waiting for the first; raises CallTimeout.")
      .def("legend", &MapClient::legend, py::arg("timeout") = py::none(),
           "The server's label legend, waiting for it; raises CallTimeout.")
      .def("latest_legend", &MapClient::latestLegend, "The legend received so far, or None.")
      .def("save", &MapClient::save, py::arg("path") = "", py::arg("timeout") = py::none(),
           "Saves the map to `path` on the server's host ('': the server's own map file).")
      .def("load", &MapClient::load, py::arg("path"), py::arg("timeout") = py::none(),
           "Replaces the map with the file `path` on the server's host.")
      .def("reset", &MapClient::reset, py::arg("timeout") = py::none(), "Empties the map.")
      .def("take_poses", &MapClient::takePoses, py::arg("timeout") = 0.0, R"doc(
The poses the server published since the last call (the client listens from its creation on),
waiting up to ``timeout`` seconds for the first when none is waiting.
)doc")
      .def("poses", &MapClient::poses, py::arg("idle_timeout") = py::none(), R"doc(
An iterator over the server's poses as they come; it ends after ``idle_timeout`` seconds without
one (None: never; Ctrl-C ends it).

    for pose in client.poses(idle_timeout=5):
        print(pose.camera_id, pose.seq, pose.pose[:3, 3])
)doc")
      .def("subscribe_poses", &MapClient::subscribePoses, py::arg("callback"), R"doc(
Calls ``callback(pose)`` on a thread of its own for every pose the server publishes, until the
returned subscription is closed. An exception in the callback is logged and counted. While a
subscription is open, take_poses() and poses() raise RuntimeError: each pose is delivered once.
)doc")
      .def_property_readonly("rejected_poses", &MapClient::rejectedPoses, "Poses that failed to decode.")
      .def("take_object_events", &MapClient::takeObjectEvents, py::arg("timeout") = 0.0, R"doc(
The updates of the map's objects published since the last call: objects that appeared, merged,
split or vanished (the server regroups its objects when a client asks for them). The first call
subscribes and gets the server's last 16 updates; a call waits up to ``timeout`` seconds for the
first when none is waiting.
)doc")
      .def_property_readonly("rejected_object_events", &MapClient::rejectedObjectEvents,
                             "Object event updates that failed to decode.")
      .def("__repr__",
           [](const MapClient& c) { return "semfuse.MapClient(domain_id=" + std::to_string(c.domain()) + ")"; });
}

}  // namespace semfuse::python
