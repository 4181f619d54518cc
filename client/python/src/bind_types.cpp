// The value types: intrinsics, the server's poses, status and legend, the query results that
// are not plain arrays (region, objects, mesh) and the objects' events.
#include <pybind11/stl.h>

#include <fstream>
#include <sstream>

#include "arrays.hpp"
#include "python_types.hpp"
#include "runtime.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/wire/image_convert.hpp"

namespace semfuse::python {
namespace {

std::string fixed(double value, int digits = 3) {
  std::ostringstream out;
  out.precision(digits);
  out << std::fixed << value;
  return out.str();
}

uint64_t countOf(const std::vector<ReasonCount>& counts, const std::optional<std::string>& reason,
                 const std::optional<std::string>& camera_id) {
  uint64_t sum = 0;
  for (const auto& c : counts)
    if ((!reason || c.reason == *reason) && (!camera_id || c.camera_id == *camera_id)) sum += c.count;
  return sum;
}

void bindIntrinsics(py::module_& m) {
  py::class_<PinholeIntrinsics>(m, "Intrinsics", "Pinhole camera intrinsics in pixels, for an image of width x height.")
      .def(py::init([](int width, int height, double fx, double fy, double cx, double cy) {
             PinholeIntrinsics k{width, height, fx, fy, cx, cy};
             if (Status ok = checkIntrinsics(k, static_cast<int>(kMaxImageSide)); !ok)
               throw py::value_error(ok.error());
             return k;
           }),
           py::arg("width"), py::arg("height"), py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"),
           "Raises ValueError for an empty image, a side above 8192 pixels, or focal lengths that are not > 0.")
      .def_static(
          "from_matrix",
          [](const py::array_t<double, py::array::c_style | py::array::forcecast>& k, int width, int height) {
            if (k.ndim() != 2 || k.shape(0) != 3 || k.shape(1) != 3) throw py::value_error("K must be 3x3");
            PinholeIntrinsics out{width, height, k.at(0, 0), k.at(1, 1), k.at(0, 2), k.at(1, 2)};
            if (Status ok = checkIntrinsics(out, static_cast<int>(kMaxImageSide)); !ok)
              throw py::value_error(ok.error());
            return out;
          },
          py::arg("K"), py::arg("width"), py::arg("height"),
          "Intrinsics from a 3x3 camera matrix K and the image size.")
      .def_readwrite("width", &PinholeIntrinsics::width)
      .def_readwrite("height", &PinholeIntrinsics::height)
      .def_readwrite("fx", &PinholeIntrinsics::fx)
      .def_readwrite("fy", &PinholeIntrinsics::fy)
      .def_readwrite("cx", &PinholeIntrinsics::cx)
      .def_readwrite("cy", &PinholeIntrinsics::cy)
      .def_property_readonly(
          "K",
          [](const PinholeIntrinsics& k) {
            py::array_t<double> out({3, 3});
            auto a = out.mutable_unchecked<2>();
            for (int r = 0; r < 3; ++r)
              for (int c = 0; c < 3; ++c) a(r, c) = 0.0;
            a(0, 0) = k.fx;
            a(1, 1) = k.fy;
            a(0, 2) = k.cx;
            a(1, 2) = k.cy;
            a(2, 2) = 1.0;
            return out;
          },
          "The 3x3 camera matrix.")
      .def("scaled", &PinholeIntrinsics::scaled, py::arg("factor"),
           "The same camera at another resolution (pixel centres stay consistent).")
      .def("__eq__",
           [](const PinholeIntrinsics& a, const PinholeIntrinsics& b) {
             return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx &&
                    a.cy == b.cy;
           })
      .def("__repr__", [](const PinholeIntrinsics& k) {
        return "semfuse.Intrinsics(width=" + std::to_string(k.width) + ", height=" + std::to_string(k.height) +
               ", fx=" + fixed(k.fx) + ", fy=" + fixed(k.fy) + ", cx=" + fixed(k.cx) + ", cy=" + fixed(k.cy) + ")";
      });
}

void bindTrackedPose(py::module_& m) {
  py::class_<TrackedPose>(m, "TrackedPose", "The pose the server used for one frame, and how it got it.")
      .def_readonly("camera_id", &TrackedPose::camera_id)
      .def_readonly("seq", &TrackedPose::seq, "The frame's sequence number.")
      .def_property_readonly(
          "stamp", [](const TrackedPose& p) { return p.stamp.seconds(); }, "The frame's time stamp, seconds.")
      .def_readonly("frame_id", &TrackedPose::frame_id)
      .def_property_readonly(
          "state", [](const TrackedPose& p) { return std::string(trackingStateName(static_cast<uint8_t>(p.state))); },
          "'given' (the frame's own pose), 'tracked', 'refined' or 'lost' (no pose, not integrated).")
      .def_readonly("posed", &TrackedPose::posed,
                    "True when the frame has a pose and goes to the map; False when tracking is lost.")
      .def_property_readonly(
          "pose", [](const TrackedPose& p) { return poseToArray(p.camera_to_world); },
          "Camera-to-world, a 4x4 float64 array.")
      .def_readonly("inlier_ratio", &TrackedPose::inlier_ratio)
      .def_readonly("residual", &TrackedPose::residual)
      .def_readonly("iterations", &TrackedPose::iterations)
      .def_readonly("track_ms", &TrackedPose::track_ms)
      .def("__repr__", [](const TrackedPose& p) {
        const auto t = p.camera_to_world.translation();
        return "semfuse.TrackedPose(camera_id='" + p.camera_id + "', seq=" + std::to_string(p.seq) + ", state='" +
               trackingStateName(static_cast<uint8_t>(p.state)) + "', position=(" + fixed(t.x()) + ", " + fixed(t.y()) +
               ", " + fixed(t.z()) + "))";
      });
}

void bindStatus(py::module_& m) {
  py::class_<ReasonCount>(m, "ReasonCount", "How many inputs were dropped or rejected for one reason.")
      .def_readonly("reason", &ReasonCount::reason)
      .def_readonly("camera_id", &ReasonCount::camera_id, "Empty when not camera specific.")
      .def_readonly("count", &ReasonCount::count)
      .def("__repr__", [](const ReasonCount& c) {
        return "semfuse.ReasonCount(reason='" + c.reason + "', camera_id='" + c.camera_id +
               "', count=" + std::to_string(c.count) + ")";
      });
  py::class_<CameraStatus>(m, "CameraStatus", "One camera as the server sees it.")
      .def_readonly("camera_id", &CameraStatus::camera_id)
      .def_property_readonly(
          "tracking_state", [](const CameraStatus& c) { return std::string(trackingStateName(c.tracking_state)); },
          "'given', 'tracked', 'refined' or 'lost'.")
      .def_readonly("last_seq", &CameraStatus::last_seq)
      .def_readonly("frames_received", &CameraStatus::frames_received)
      .def_readonly("frames_posed", &CameraStatus::frames_posed, "Frames given or tracked a pose.")
      .def_readonly("frames_integrated", &CameraStatus::frames_integrated, "Of the posed frames, those fused.")
      .def_readonly("frames_skipped", &CameraStatus::frames_skipped,
                    "Of the posed frames, those integration passed over for a newer one (labels still fused).")
      .def_readonly("frames_lost", &CameraStatus::frames_lost)
      .def_readonly("frame_rate_hz", &CameraStatus::frame_rate_hz)
      .def_readonly("last_frame_age_s", &CameraStatus::last_frame_age_s)
      .def_readonly("stale", &CameraStatus::stale)
      .def_readonly("lost_reason", &CameraStatus::lost_reason)
      .def_readonly("frames_since_lost", &CameraStatus::frames_since_lost)
      .def_readonly("relocalisations", &CameraStatus::relocalisations)
      .def("__repr__", [](const CameraStatus& c) {
        return "semfuse.CameraStatus(camera_id='" + c.camera_id +
               "', frames_integrated=" + std::to_string(c.frames_integrated) + ")";
      });
  py::class_<ServerError>(m, "ErrorRecord", "One of the last errors the server logged.")
      .def_readonly("stamp", &ServerError::stamp_s, "Seconds since the server started.")
      .def_readonly("source", &ServerError::source)
      .def_readonly("message", &ServerError::message)
      .def("__repr__", [](const ServerError& e) {
        return "semfuse.ErrorRecord(source='" + e.source + "', message='" + e.message + "')";
      });
  py::class_<StageTiming>(m, "StageTiming",
                          "How long one stage of the server's work took: runs since the server started; median, "
                          "95th percentile and maximum over the last (at most 1,000) runs.")
      .def_readonly("stage", &StageTiming::stage)
      .def_readonly("count", &StageTiming::count)
      .def_readonly("p50_ms", &StageTiming::p50_ms)
      .def_readonly("p95_ms", &StageTiming::p95_ms)
      .def_readonly("max_ms", &StageTiming::max_ms)
      .def("__repr__", [](const StageTiming& t) {
        return "semfuse.StageTiming(stage='" + t.stage + "', count=" + std::to_string(t.count) + ")";
      });

  py::class_<ServerStatus>(m, "ServerStatus",
                           "The server's counters and state: what it received, integrated, dropped (by reason) and "
                           "rejected (by reason), per camera, and the map's size.")
      .def_readonly("server_id", &ServerStatus::server_id)
      .def_readonly("version", &ServerStatus::version)
      .def_readonly("uptime_s", &ServerStatus::uptime_s)
      .def_readonly("frames_received", &ServerStatus::frames_received)
      .def_readonly("frames_posed", &ServerStatus::frames_posed)
      .def_readonly("frames_integrated", &ServerStatus::frames_integrated)
      .def_readonly("frames_skipped", &ServerStatus::frames_skipped)
      .def_readonly("frames_lost", &ServerStatus::frames_lost)
      .def_readonly("segmentations_received", &ServerStatus::segmentations_received)
      .def_readonly("segmentations_integrated", &ServerStatus::segmentations_integrated)
      .def_readonly("dropped", &ServerStatus::dropped, "Inputs dropped (queue full, waited too long, ...), by reason.")
      .def_readonly("rejected", &ServerStatus::rejected, "Inputs rejected as malformed or inconsistent, by reason.")
      .def_readonly("queued_frames", &ServerStatus::queued_frames)
      .def_readonly("pending_segmentations", &ServerStatus::pending_segmentations)
      .def_readonly("history_frames", &ServerStatus::history_frames)
      .def_readonly("map_revision", &ServerStatus::map_revision, "Raised by every change to the map.")
      .def_readonly("distance_field_revision", &ServerStatus::distance_field_revision,
                    "The map revision the distance field reflects (0 without --esdf).")
      .def_readonly("snapshot_bytes", &ServerStatus::snapshot_bytes,
                    "Bytes of the map's copies kept for queries that run without its lock (region, objects, mesh).")
      .def_readonly("voxel_size", &ServerStatus::voxel_size)
      .def_readonly("truncation", &ServerStatus::truncation)
      .def_readonly("allocated_voxels", &ServerStatus::allocated_voxels)
      .def_readonly("allocated_blocks", &ServerStatus::allocated_blocks)
      .def_readonly("map_bytes", &ServerStatus::map_bytes)
      .def_readonly("rss_bytes", &ServerStatus::rss_bytes)
      .def_readonly("cameras", &ServerStatus::cameras)
      .def_readonly("last_errors", &ServerStatus::last_errors)
      .def_readonly("map_file", &ServerStatus::map_file)
      .def_readonly("last_save_ok", &ServerStatus::last_save_ok)
      .def_readonly("last_save_age_s", &ServerStatus::last_save_age_s, "Negative: never saved.")
      .def_readonly(
          "stages", &ServerStatus::stages,
          "Where the server's time goes: frame_decode, frame_queue, track, integration_queue, integrate, late_labels, "
          "map_update, distance_field (those that ran).")
      .def(
          "dropped_count",
          [](const ServerStatus& s, const std::optional<std::string>& reason,
             const std::optional<std::string>& camera) { return countOf(s.dropped, reason, camera); },
          py::arg("reason") = py::none(), py::arg("camera_id") = py::none(),
          "Inputs dropped for `reason` (None: any) by `camera_id` (None: any).")
      .def(
          "rejected_count",
          [](const ServerStatus& s, const std::optional<std::string>& reason,
             const std::optional<std::string>& camera) { return countOf(s.rejected, reason, camera); },
          py::arg("reason") = py::none(), py::arg("camera_id") = py::none(),
          "Inputs rejected for `reason` (None: any) by `camera_id` (None: any).")
      .def("__repr__", [](const ServerStatus& s) {
        return "semfuse.ServerStatus(frames_integrated=" + std::to_string(s.frames_integrated) +
               ", segmentations_integrated=" + std::to_string(s.segmentations_integrated) +
               ", allocated_voxels=" + std::to_string(s.allocated_voxels) + ")";
      });
}

void bindLegend(py::module_& m) {
  py::class_<LabelInfo>(m, "LabelInfo", "A label of the legend: id, name and display colour.")
      .def_readonly("id", &LabelInfo::id)
      .def_readonly("name", &LabelInfo::name)
      .def_property_readonly(
          "rgb", [](const LabelInfo& l) { return py::make_tuple(l.rgb[0], l.rgb[1], l.rgb[2]); }, "(red, green, blue).")
      .def("__repr__", [](const LabelInfo& l) {
        return "semfuse.LabelInfo(id=" + std::to_string(l.id) + ", name='" + l.name + "')";
      });
  py::class_<LabelLegend>(m, "Legend",
                          "The server's labels: ids, names, colours, and which are background (never change a "
                          "voxel's label).")
      .def_readonly("name", &LabelLegend::name)
      .def_readonly("labels", &LabelLegend::labels, "Sorted by id.")
      .def_readonly("background_ids", &LabelLegend::background_ids)
      .def(
          "name_of",
          [](const LabelLegend& l, LabelId id) -> std::optional<std::string> {
            const LabelInfo* info = l.find(id);
            return info ? std::optional<std::string>(info->name) : std::nullopt;
          },
          py::arg("label"), "The label's name, or None when the legend has no such label.")
      .def(
          "id_of",
          [](const LabelLegend& l, const std::string& name) -> std::optional<LabelId> {
            for (const auto& info : l.labels)
              if (info.name == name) return info.id;
            return std::nullopt;
          },
          py::arg("name"), "The id of the label called `name`, or None.")
      .def(
          "color_of",
          [](const LabelLegend& l, LabelId id) {
            const auto rgb = l.colorOf(id);
            return py::make_tuple(rgb[0], rgb[1], rgb[2]);
          },
          py::arg("label"), "(red, green, blue) of a label; a fixed colour for ids missing from the legend.")
      .def("is_background", &LabelLegend::isBackground, py::arg("label"),
           "True for labels that never change a voxel's label (0, unlabeled, and the legend's own).")
      .def(
          "colorize",
          [](const LabelLegend& l, const py::handle& labels) {
            auto image = labelsFromArray(labels);
            if (!image) throw py::value_error(image.error());
            return imageToArray(wire::colorizeLabels(image.value(), l));
          },
          py::arg("labels"), "A (rows, cols) label image as a (rows, cols, 3) uint8 RGB image in the legend's colours.")
      .def("__contains__", &LabelLegend::contains)
      .def("__len__", [](const LabelLegend& l) { return l.labels.size(); })
      .def("__repr__", [](const LabelLegend& l) {
        return "semfuse.Legend(name='" + l.name + "', labels=" + std::to_string(l.labels.size()) + ")";
      });
}

void bindQueryResults(py::module_& m) {
  py::class_<LabelArea>(m, "LabelArea", "The surface of one label in a region.")
      .def_readonly("label", &LabelArea::label)
      .def_readonly("surface_voxels", &LabelArea::surface_voxels)
      .def_readonly("area_m2", &LabelArea::area_m2)
      .def("__repr__", [](const LabelArea& a) {
        return "semfuse.LabelArea(label=" + std::to_string(a.label) + ", area_m2=" + fixed(a.area_m2, 4) + ")";
      });
  py::class_<RegionSummary>(m, "RegionSummary", "What the map holds in a box.")
      .def_readonly("histogram", &RegionSummary::histogram, "Surface per label.")
      .def_readonly("observed_voxels", &RegionSummary::observed_voxels)
      .def_readonly("occupied_voxels", &RegionSummary::occupied_voxels)
      .def_readonly("free_voxels", &RegionSummary::free_voxels)
      .def_readonly("occupancy", &RegionSummary::occupancy)
      .def("__repr__", [](const RegionSummary& r) {
        return "semfuse.RegionSummary(observed_voxels=" + std::to_string(r.observed_voxels) +
               ", labels=" + std::to_string(r.histogram.size()) + ")";
      });
  py::class_<ObjectInstance>(m, "ObjectInstance", "A connected labeled surface of the map.")
      .def_readonly("id", &ObjectInstance::id)
      .def_readonly("label", &ObjectInstance::label)
      .def_property_readonly(
          "bbox_min", [](const ObjectInstance& o) { return vectorToArray(o.bbox_min); }, "World frame, metres.")
      .def_property_readonly(
          "bbox_max", [](const ObjectInstance& o) { return vectorToArray(o.bbox_max); }, "World frame, metres.")
      .def_property_readonly(
          "centroid", [](const ObjectInstance& o) { return vectorToArray(o.centroid); }, "World frame, metres.")
      .def_readonly("voxel_count", &ObjectInstance::voxel_count)
      .def_readonly("mean_confidence", &ObjectInstance::mean_confidence)
      .def_readonly("area_m2", &ObjectInstance::area_m2, "Of its surface.")
      .def_property_readonly(
          "box_center", [](const ObjectInstance& o) { return vectorToArray(o.box_center); },
          "The oriented box's centre, world frame, metres.")
      .def_property_readonly(
          "box_half_extents", [](const ObjectInstance& o) { return vectorToArray(o.box_half_extents); },
          "Half the oriented box's size along each of its axes, metres.")
      .def_property_readonly(
          "box_rotation",
          [](const ObjectInstance& o) {
            const Eigen::Matrix3d r = o.box_rotation.normalized().toRotationMatrix();
            std::vector<double> rows(9);
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j) rows[static_cast<std::size_t>(3 * i + j)] = r(i, j);
            return vectorToArray(std::move(rows), {3, 3});
          },
          "(3, 3) rotation from the box's axes to the world: its columns are the axes. The box is upright "
          "around the up axis when the server knows it, else along the surface's principal axes.")
      .def_readonly("fragment", &ObjectInstance::fragment, "A piece too small to be an object.")
      .def_property_readonly(
          "frames",
          [](const ObjectInstance& o) {
            std::vector<std::pair<std::string, uint64_t>> frames;
            for (const FrameRef& f : o.frames) frames.emplace_back(f.camera_id, f.seq);
            return frames;
          },
          "(camera_id, seq) of the frames that saw it, those that saw most of its surface first (at most 16).")
      .def_readonly("frame_count", &ObjectInstance::frame_count,
                    "How many frames saw it, as far as its 8^3 leaves remember (each the latest 16 that saw it).")
      .def("__repr__", [](const ObjectInstance& o) {
        return "semfuse.ObjectInstance(id=" + std::to_string(o.id) + ", label=" + std::to_string(o.label) +
               ", voxel_count=" + std::to_string(o.voxel_count) + ")";
      });
  py::class_<Mesh>(m, "Mesh",
                   "The map's mesh as arrays (vertices, faces, per-vertex normals, colours, labels, scores) and as the "
                   "PLY file the server sent.")
      .def_readonly("vertices", &Mesh::vertices, "(N, 3) float32, world frame, metres.")
      .def_readonly("faces", &Mesh::faces, "(M, 3) uint32 vertex indices, counter-clockwise seen from free space.")
      .def_readonly("normals", &Mesh::normals, "(N, 3) float32 unit normals (None if the PLY has none).")
      .def_readonly("colors", &Mesh::colors, "(N, 3) uint8 RGB, the legend's colour of each vertex's label.")
      .def_readonly("labels", &Mesh::labels, "(N,) uint16 vertex labels.")
      .def_readonly("scores", &Mesh::scores, "(N,) float32 label scores.")
      .def_readonly("ply", &Mesh::ply, "The binary PLY file (bytes).")
      .def(
          "save",
          [](const Mesh& mesh, const std::string& path) {
            const auto bytes = static_cast<std::string>(mesh.ply);
            std::ofstream out(path, std::ios::binary);
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
            if (!out) throw py::value_error("cannot write " + path);
          },
          py::arg("path"), "Writes the PLY file to `path`.")
      .def("__repr__", [](const Mesh& mesh) {
        return "semfuse.Mesh(vertices=" + std::to_string(py::len(mesh.vertices)) +
               ", faces=" + std::to_string(py::len(mesh.faces)) + ")";
      });
}

void bindObjectEvents(py::module_& m) {
  py::class_<ObjectEvent>(m, "ObjectEvent", "One change of the map's objects.")
      .def_property_readonly(
          "kind", [](const ObjectEvent& e) { return std::string(objectEventKindName(e.kind)); },
          "'appeared', 'merged', 'split' or 'vanished'.")
      .def_readonly("id", &ObjectEvent::id, "The object the event is about.")
      .def_readonly("label", &ObjectEvent::label, "Its class.")
      .def_readonly("others", &ObjectEvent::others,
                    "merged: the ids that joined `id` and are gone; split: the new ids that came apart from it.")
      .def("__repr__", [](const ObjectEvent& e) {
        return "semfuse.ObjectEvent(kind='" + std::string(objectEventKindName(e.kind)) +
               "', id=" + std::to_string(e.id) + ", label=" + std::to_string(e.label) + ")";
      });
  py::class_<ObjectEvents>(m, "ObjectEvents", "The events of one update of the map's objects.")
      .def_readonly("update", &ObjectEvents::update, "1, 2, ... since the server started.")
      .def_property_readonly(
          "stamp", [](const ObjectEvents& e) { return e.stamp.seconds(); }, "Wall clock of the update, seconds.")
      .def_readonly("object_count", &ObjectEvents::object_count, "Objects after it (fragments not counted).")
      .def_readonly("events", &ObjectEvents::events)
      .def("__repr__", [](const ObjectEvents& e) {
        return "semfuse.ObjectEvents(update=" + std::to_string(e.update) +
               ", events=" + std::to_string(e.events.size()) + ")";
      });
}

}  // namespace

void bindTypes(py::module_& m) {
  bindIntrinsics(m);
  bindTrackedPose(m);
  bindStatus(m);
  bindLegend(m);
  bindQueryResults(m);
  bindObjectEvents(m);
}

}  // namespace semfuse::python
