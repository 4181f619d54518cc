// semfuse-query: one subcommand per service of the semfuse server (raycast, labels-at, region,
// objects, mesh, status, save, load, reset), the poses topic (poses) and the distance field's
// services (distance, occupancy, semantic-distance, semantic-slice, segment-check:
// distance_commands.hpp). Exit codes: 0 ok, 2 usage, 3 server error, 4 timeout.
#include <chrono>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "distance_commands.hpp"
#include "raycast_output.hpp"
#include "report.hpp"
#include "semfuse/cli/command_line.hpp"
#include "semfuse/cli/exit_codes.hpp"
#include "semfuse/cli/stop_signal.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/core/legend_io.hpp"
#include "semfuse/core/logging.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/participant.hpp"
#include "trajectory_file.hpp"

namespace {

using namespace semfuse;
using client::Failure;

struct Options {
  cli::CommonOptions common;
  double timeout_s = 10.0;
  bool json = false;
  std::string legend;  // fallback when the server publishes none
  // raycast
  std::vector<std::string> pose;
  std::string intrinsics_file;
  PinholeIntrinsics intrinsics{640, 480, 585.0, 585.0, 320.0, 240.0};  // 7-Scenes' Kinect
  std::vector<std::string> layers{"depth", "normals", "labels", "confidence", "color"};
  float max_range = 0.0F;
  std::string out;
  // labels-at
  std::vector<double> points;
  // region / mesh
  std::vector<double> box_min;
  std::vector<double> box_max;
  // objects
  std::string label = "0";
  unsigned min_voxels = 0;
  std::vector<double> near;
  double radius = 0.5;
  bool fragments = false;
  double max_age_s = 0.0;
  // mesh
  uint32_t object_id = 0;
  // status
  bool watch = false;
  double interval_s = 1.0;
  // save / load
  std::string path;
  // poses
  std::string format = "tum";
  std::string camera;
  uint64_t max_poses = 0;
  double duration_s = 0.0;
  double idle_s = 0.0;
  bool include_lost = false;
};

int exitCodeOf(Failure failure) {
  switch (failure) {
    case Failure::kServer:
      return cli::kExitServerError;
    case Failure::kTimeout:
      return cli::kExitTimeout;
    default:
      return cli::kExitFailure;
  }
}

template <class T>
int reportFailure(const client::CallResult<T>& result) {
  spdlog::error("{}", result.error());
  return exitCodeOf(result.failure());
}

// --pose: 12 numbers (row-major 3x4 camera-to-world) or one pose.txt file (4x4 or 3x4).
Result<Pose> parsePose(const std::vector<std::string>& values) {
  if (values.size() == 1) return datasets::readSevenScenesPose(values.front());
  if (values.size() != 12)
    return makeError("--pose takes 12 numbers or one file, not " + std::to_string(values.size()) + " values");
  double numbers[12];
  for (int i = 0; i < 12; ++i) {
    try {
      numbers[i] = std::stod(values[i]);
    } catch (const std::exception&) {
      return makeError("--pose: '" + values[i] + "' is not a number");
    }
  }
  Pose pose = Pose::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = numbers[r * 4 + c];
  return pose;
}

Result<uint32_t> parseLayers(const std::vector<std::string>& names) {
  uint32_t layers = 0;
  for (const auto& name : names) {
    if (name == "depth") layers |= client::kDepthLayer;
    else if (name == "normals") layers |= client::kNormalsLayer;
    else if (name == "labels") layers |= client::kLabelsLayer;
    else if (name == "confidence") layers |= client::kConfidenceLayer;
    else if (name == "color") layers |= client::kColorLayer;
    else return makeError("unknown layer '" + name + "' (depth, normals, labels, confidence, color)");
  }
  return layers;
}

Result<client::Box> parseBox(const std::vector<double>& min, const std::vector<double>& max) {
  if (min.size() != 3 || max.size() != 3) return makeError("--min and --max take 3 numbers each");
  client::Box box{{min[0], min[1], min[2]}, {max[0], max[1], max[2]}};
  if ((box.max.array() < box.min.array()).any()) return makeError("--max must not be below --min");
  return box;
}

class Query {
 public:
  explicit Query(const Options& o)
      : o_(o),
        participant_(o.common.domain_id < 0 ? DDS_DOMAIN_DEFAULT : static_cast<dds_domainid_t>(o.common.domain_id)),
        map_(participant_),
        timeout_(static_cast<long>(o.timeout_s * 1000)) {}

  int raycast() {
    auto pose = parsePose(o_.pose);
    if (!pose) return usage(pose.error());
    auto layers = parseLayers(o_.layers);
    if (!layers) return usage(layers.error());
    PinholeIntrinsics intrinsics = o_.intrinsics;
    if (!o_.intrinsics_file.empty()) {
      auto k = datasets::readSevenScenesIntrinsics(o_.intrinsics_file);
      if (!k) return usage(k.error());
      intrinsics = {o_.intrinsics.width, o_.intrinsics.height, k.value().fx, k.value().fy, k.value().cx, k.value().cy};
    }
    auto images = map_.raycast(pose.value(), intrinsics, layers.value(), timeout_, o_.max_range);
    if (!images) return reportFailure(images);
    auto written = tools::writeRaycastImages(images.value(), legend(), o_.out);
    if (!written) {
      spdlog::error("{}", written.error());
      return cli::kExitFailure;
    }
    for (const auto& file : written.value()) std::cout << file.string() << "\n";
    return cli::kExitOk;
  }

  int labelsAt() {
    if (o_.points.empty() || o_.points.size() % 3 != 0) return usage("--point takes 3 numbers per point");
    std::vector<Eigen::Vector3d> points;
    for (std::size_t i = 0; i < o_.points.size(); i += 3)
      points.emplace_back(o_.points[i], o_.points[i + 1], o_.points[i + 2]);
    auto samples = map_.labelsAt(points, timeout_);
    if (!samples) return reportFailure(samples);
    std::cout << (o_.json ? tools::samplesJson(points, samples.value(), legend())
                          : tools::samplesTable(points, samples.value(), legend()));
    return cli::kExitOk;
  }

  int region() {
    auto box = parseBox(o_.box_min, o_.box_max);
    if (!box) return usage(box.error());
    auto summary = map_.region(box.value(), timeout_);
    if (!summary) return reportFailure(summary);
    std::cout << (o_.json ? tools::regionJson(summary.value(), legend())
                          : tools::regionTable(summary.value(), legend()));
    return cli::kExitOk;
  }

  int objects() {
    client::ObjectsRequest request;
    auto label = labelOf(o_.label);
    if (!label) return usage(label.error());
    request.label = label.value();
    request.min_voxels = o_.min_voxels;
    if (!o_.near.empty()) request.near = Eigen::Vector3d(o_.near[0], o_.near[1], o_.near[2]);
    request.radius = o_.radius;
    request.include_fragments = o_.fragments;
    request.max_age_s = o_.max_age_s;
    auto objects = map_.objects(request, timeout_);
    if (!objects) return reportFailure(objects);
    std::cout << (o_.json ? tools::objectsJson(objects.value(), legend())
                          : tools::objectsTable(objects.value(), legend()));
    return cli::kExitOk;
  }

  int mesh() {
    std::optional<client::Box> box;
    if (!o_.box_min.empty() || !o_.box_max.empty()) {
      auto parsed = parseBox(o_.box_min, o_.box_max);
      if (!parsed) return usage(parsed.error());
      box = parsed.value();
    }
    auto mesh = map_.mesh(box, timeout_, o_.object_id);
    if (!mesh) return reportFailure(mesh);
    std::ofstream file(o_.out, std::ios::binary);
    file.write(reinterpret_cast<const char*>(mesh.value().ply.data()),
               static_cast<std::streamsize>(mesh.value().ply.size()));
    if (!file) {
      spdlog::error("cannot write {}", o_.out);
      return cli::kExitFailure;
    }
    spdlog::info("{}: {} vertices, {} faces, {} bytes", o_.out, mesh.value().vertex_count, mesh.value().face_count,
                 mesh.value().ply.size());
    return cli::kExitOk;
  }

  int status() {
    // The status topic is transient-local: a running server's latest status arrives at once.
    // Without one in time, ask for it (an older server, or a status not published yet).
    auto status = map_.waitForStatus(timeout_);
    if (!status) {
      auto stats = map_.stats(timeout_);
      if (!stats) return reportFailure(stats);
      status = stats.value();
    }
    print(*status);
    while (o_.watch && !cli::stopRequested()) {
      std::this_thread::sleep_for(std::chrono::duration<double>(o_.interval_s));
      if (auto latest = map_.latestStatus()) print(*latest);
    }
    return cli::kExitOk;
  }

  // Records the poses topic into a trajectory file until Ctrl-C, --frames, --duration or --idle.
  // Lines are flushed as they come: an interrupted recording keeps what it had.
  int poses() {
    const auto format = tools::trajectoryFormatNamed(o_.format);
    if (!format) return usage("--format must be tum, kitti or csv, got '" + o_.format + "'");
    std::ofstream file(o_.out);
    if (!file) return usage("cannot write " + o_.out);
    file << tools::trajectoryHeader(*format) << std::flush;
    spdlog::info("recording poses{} into {} ({}); Ctrl-C stops", o_.camera.empty() ? "" : " of camera " + o_.camera,
                 o_.out, o_.format);
    const auto start = std::chrono::steady_clock::now();
    auto last_pose = start;
    uint64_t written = 0, lost = 0;
    std::map<std::string, uint64_t> per_camera;
    auto seconds_since = [](std::chrono::steady_clock::time_point t) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    while (!cli::stopRequested()) {
      if (o_.max_poses > 0 && written >= o_.max_poses) break;
      if (o_.duration_s > 0 && seconds_since(start) >= o_.duration_s) break;
      if (o_.idle_s > 0 && written > 0 && seconds_since(last_pose) >= o_.idle_s) break;
      for (const TrackedPose& pose : map_.takePoses(std::chrono::milliseconds(200))) {
        if (!o_.camera.empty() && pose.camera_id != o_.camera) continue;
        last_pose = std::chrono::steady_clock::now();
        if (!pose.posed) ++lost;
        if (!pose.posed && !o_.include_lost) continue;
        if (o_.max_poses > 0 && written >= o_.max_poses) break;
        file << tools::trajectoryLine(pose, *format);
        ++written;
        ++per_camera[pose.camera_id];
      }
      file.flush();
    }
    if (!file) {
      spdlog::error("writing {} failed", o_.out);
      return cli::kExitFailure;
    }
    if (per_camera.size() > 1 && *format != tools::TrajectoryFormat::kCsv)
      spdlog::warn("{} cameras in one {} file: pass --camera to record one trajectory", per_camera.size(), o_.format);
    spdlog::info("{} poses written to {}, {} frames lost (no pose){}", written, o_.out, lost,
                 map_.rejectedPoses() > 0 ? fmt::format(", {} malformed poses left out", map_.rejectedPoses()) : "");
    return cli::kExitOk;
  }

  int distanceCommand(const tools::DistanceCommands& commands) {
    return commands.run(map_, timeout_, [this]() -> const LabelLegend& { return legend(); });
  }

  int admin(const std::string& command) {
    client::CallResult<client::ServerStatus> result = command == "save"   ? map_.save(o_.path, timeout_)
                                                      : command == "load" ? map_.load(o_.path, timeout_)
                                                                          : map_.reset(timeout_);
    if (!result) return reportFailure(result);
    spdlog::info("{}: done", command);
    if (o_.json) std::cout << tools::statusJson(result.value()) << "\n";
    return cli::kExitOk;
  }

 private:
  int usage(const std::string& message) const {
    spdlog::error("{}", message);
    return cli::kExitUsage;
  }

  void print(const client::ServerStatus& status) const {
    std::cout << (o_.json ? tools::statusJson(status) + "\n" : tools::statusTable(status)) << std::flush;
  }

  // The server's legend (published transient-local), else --legend, else an empty one (labels
  // then get generated colours and "label N" names).
  // A label id, or a name of the server's legend.
  Result<LabelId> labelOf(const std::string& text) {
    if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
      const unsigned long id = std::stoul(text.size() > 6 ? std::string("70000") : text);
      if (id > 65535) return makeError("label id " + text + " is out of range");
      return static_cast<LabelId>(id);
    }
    for (const LabelInfo& info : legend().labels)
      if (info.name == text) return info.id;
    return makeError("no label named '" + text + "' in the legend '" + legend().name + "'");
  }

  const LabelLegend& legend() {
    if (!legend_) {
      legend_ = map_.waitForLegend(std::chrono::milliseconds(std::min<long>(2000, timeout_.count())));
      if (!legend_ && !o_.legend.empty()) {
        auto fallback = resolveLegend(o_.legend);
        if (fallback) legend_ = fallback.value();
        else spdlog::warn("{}", fallback.error());
      }
      if (!legend_) legend_ = LabelLegend{};
    }
    return *legend_;
  }

  const Options& o_;
  dds::Participant participant_;
  client::MapClient map_;
  std::chrono::milliseconds timeout_;
  std::optional<LabelLegend> legend_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Queries a semfuse map server. Exit codes: 0 ok, 2 usage, 3 server error, 4 timeout.", "semfuse-query"};
  app.require_subcommand(1);
  Options o;
  cli::addCommonOptions(app, o.common);
  app.add_option("--timeout", o.timeout_s, "seconds to wait for the server's reply")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--legend", o.legend, "legend for names and colours when the server publishes none");

  auto* raycast = app.add_subcommand("raycast", "render the map from a camera pose into --out DIR");
  raycast->add_option("--pose", o.pose, "camera-to-world: 12 numbers (row-major 3x4) or a pose.txt file")
      ->required()
      ->expected(1, 12);
  raycast->add_option("--intrinsics", o.intrinsics_file, "a 7-Scenes camera-intrinsics.txt (3x3 K)");
  raycast->add_option("--width", o.intrinsics.width, "image width")->check(CLI::PositiveNumber)->capture_default_str();
  raycast->add_option("--height", o.intrinsics.height, "image height")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  raycast->add_option("--fx", o.intrinsics.fx, "focal length x, pixels")->capture_default_str();
  raycast->add_option("--fy", o.intrinsics.fy, "focal length y, pixels")->capture_default_str();
  raycast->add_option("--cx", o.intrinsics.cx, "principal point x")->capture_default_str();
  raycast->add_option("--cy", o.intrinsics.cy, "principal point y")->capture_default_str();
  raycast->add_option("--layers", o.layers, "depth normals labels confidence color")
      ->delimiter(',')
      ->capture_default_str();
  raycast->add_option("--max-range", o.max_range, "metres (0 = server default)");
  raycast->add_option("--out", o.out, "output folder")->required();

  auto* labels_at = app.add_subcommand("labels-at", "label, confidence, tsdf and weight at points");
  labels_at->add_option("--point", o.points, "X Y Z (repeat for more points)")
      ->required()
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  labels_at->add_flag("--json", o.json, "print JSON");

  auto* region = app.add_subcommand("region", "label histogram and occupancy of a box");
  region->add_option("--min", o.box_min, "X Y Z")->required()->expected(3);
  region->add_option("--max", o.box_max, "X Y Z")->required()->expected(3);
  region->add_flag("--json", o.json, "print JSON");

  auto* objects = app.add_subcommand("objects", "the map's object instances (ids kept while the map grows)");
  objects->add_option("--label", o.label, "only this label: a name of the legend or an id (0 = all)")
      ->capture_default_str();
  objects->add_option("--min-voxels", o.min_voxels, "smallest instance, surface voxels")->capture_default_str();
  objects->add_option("--near", o.near, "only objects whose surface comes within --radius of X Y Z")->expected(3);
  objects->add_option("--radius", o.radius, "metres, with --near")->check(CLI::PositiveNumber)->capture_default_str();
  objects->add_flag("--fragments", o.fragments, "also the pieces too small to be objects");
  objects
      ->add_option("--max-age", o.max_age_s,
                   "seconds: the objects the server keeps up to date in the background will do when grouped from "
                   "a map at most this much older (an answer at once while the map grows; 0 = the map as it is)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  objects->add_flag("--json", o.json, "print JSON");

  auto* mesh = app.add_subcommand("mesh", "labeled mesh as a PLY file");
  mesh->add_option("--out", o.out, "PLY file to write")->required();
  mesh->add_option("--min", o.box_min, "box corner X Y Z (optional)")->expected(3);
  mesh->add_option("--max", o.box_max, "box corner X Y Z (optional)")->expected(3);
  mesh->add_option("--object", o.object_id, "only this object's surface (an id from objects)");

  auto* status = app.add_subcommand("status", "server counters, map size, cameras, errors");
  status->add_flag("--json", o.json, "print JSON");
  status->add_flag("--watch", o.watch, "keep printing until Ctrl-C");
  status->add_option("--interval", o.interval_s, "seconds between prints with --watch")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();

  auto* save = app.add_subcommand("save", "save the map (default: the server's map file)");
  save->add_option("path", o.path, "file on the server's machine");
  save->add_flag("--json", o.json, "print the status after saving as JSON");
  auto* load = app.add_subcommand("load", "replace the map by a saved one");
  load->add_option("path", o.path, "file on the server's machine (default: its map file)");
  load->add_flag("--json", o.json, "print the status after loading as JSON");
  auto* reset = app.add_subcommand("reset", "clear the map");
  reset->add_flag("--json", o.json, "print the status after the reset as JSON");

  auto* poses = app.add_subcommand("poses", "record the server's camera poses into a trajectory file");
  poses->add_option("--out", o.out, "trajectory file to write")->required();
  poses->add_option("--format", o.format, "tum (timestamp tx ty tz qx qy qz qw), kitti (3x4 per line) or csv")
      ->check(CLI::IsMember({"tum", "kitti", "csv"}))
      ->capture_default_str();
  poses->add_option("--camera", o.camera, "only this camera's poses (default: every camera)");
  poses->add_option("--frames", o.max_poses, "stop after this many poses (0 = no limit)")->capture_default_str();
  poses->add_option("--duration", o.duration_s, "stop after this many seconds (0 = no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  poses->add_option("--idle", o.idle_s, "stop when no pose came for this many seconds after the first (0 = never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  poses->add_flag("--include-lost", o.include_lost,
                  "also write frames whose tracking was lost (at the camera's last pose; csv says which)");

  tools::DistanceOptions distance_options;
  const tools::DistanceCommands distance_commands(app, distance_options);

  if (const int code = cli::parseCommandLine(app, argc, argv); code >= 0) return code;
  if (Status s = setupLogging("semfuse-query", o.common.log_level); !s) {
    spdlog::error("{}", s.error());
    return cli::kExitUsage;
  }
  cli::installStopHandler();
  try {
    Query query(o);
    if (raycast->parsed()) return query.raycast();
    if (labels_at->parsed()) return query.labelsAt();
    if (region->parsed()) return query.region();
    if (objects->parsed()) return query.objects();
    if (mesh->parsed()) return query.mesh();
    if (status->parsed()) return query.status();
    if (save->parsed()) return query.admin("save");
    if (load->parsed()) return query.admin("load");
    if (reset->parsed()) return query.admin("reset");
    if (poses->parsed()) return query.poses();
    if (distance_commands.parsed()) return query.distanceCommand(distance_commands);
  } catch (const dds::DdsError& e) {
    spdlog::error("DDS: {}", e.what());
    return cli::kExitFailure;
  }
  return cli::kExitUsage;
}
