#include "distance_commands.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>

#include "report.hpp"
#include "semfuse/cli/exit_codes.hpp"

namespace semfuse::tools {
namespace {

using client::Failure;

template <class T>
int reportFailure(const client::CallResult<T>& result) {
  spdlog::error("{}", result.error());
  switch (result.failure()) {
    case Failure::kServer:
      return cli::kExitServerError;
    case Failure::kTimeout:
      return cli::kExitTimeout;
    default:
      return cli::kExitFailure;
  }
}

int usage(const std::string& message) {
  spdlog::error("{}", message);
  return cli::kExitUsage;
}

std::vector<Eigen::Vector3d> triples(const std::vector<double>& v) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) out.emplace_back(v[i], v[i + 1], v[i + 2]);
  return out;
}

// Label ids from ids or legend names.
Result<std::vector<LabelId>> labelIds(const std::vector<std::string>& names, const LabelLegend& legend) {
  std::vector<LabelId> ids;
  for (const std::string& name : names) {
    char* end = nullptr;
    const long id = std::strtol(name.c_str(), &end, 10);
    if (!name.empty() && *end == '\0') {
      if (id < 0 || id > 65535) return makeError("--label " + name + " is not a label id (0-65535)");
      ids.push_back(static_cast<LabelId>(id));
      continue;
    }
    const LabelInfo* found = nullptr;
    for (const LabelInfo& info : legend.labels)
      if (info.name == name) found = &info;
    if (!found)
      return makeError("--label '" + name + "' is neither an id nor a name in the legend '" + legend.name + "'");
    ids.push_back(found->id);
  }
  return ids;
}

std::string number(double v, int decimals = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

const char* statusName(client::SegmentStatus status) {
  switch (status) {
    case client::SegmentStatus::kFree:
      return "free";
    case client::SegmentStatus::kCollision:
      return "collision";
    case client::SegmentStatus::kUnknown:
      return "unknown";
  }
  return "?";
}

}  // namespace

DistanceCommands::DistanceCommands(CLI::App& app, DistanceOptions& o) : o_(o) {
  distance_ = app.add_subcommand("distance", "signed distance and gradient of the distance field at points (--esdf)");
  distance_->add_option("--point", o.points, "X Y Z (repeat for more points)")
      ->required()
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  distance_->add_flag("--json", o.json, "print JSON");

  occupancy_ = app.add_subcommand("occupancy", "2D occupancy grid of a height band as a PNG + YAML (map_server's)");
  occupancy_->add_option("--min-z", o.z_min, "bottom of the band, metres")->capture_default_str();
  occupancy_->add_option("--max-z", o.z_max, "top of the band, metres")->capture_default_str();
  occupancy_->add_option("--min", o.min, "box corner X Y (default: the observed extent)")->expected(2);
  occupancy_->add_option("--max", o.max, "box corner X Y")->expected(2);
  occupancy_->add_option("--inflation", o.inflation, "inflation radius, metres")->capture_default_str();
  occupancy_->add_option("--out", o.out, "PNG to write (the YAML goes beside it)")->required();

  semantic_distance_ =
      app.add_subcommand("semantic-distance", "distance and direction to the nearest surface of labels at points");
  semantic_distance_->add_option("--label", o.labels, "label id or name (repeat for a set)")->required();
  semantic_distance_->add_option("--point", o.points, "X Y Z (repeat for more points)")
      ->required()
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  semantic_distance_->add_flag("--json", o.json, "print JSON");

  semantic_slice_ = app.add_subcommand("semantic-slice",
                                       "distance to the nearest surface of labels over a horizontal plane, as images");
  semantic_slice_->add_option("--label", o.labels, "label id or name (repeat for a set)")->required();
  semantic_slice_->add_option("--z", o.z, "height of the plane, metres")->capture_default_str();
  semantic_slice_->add_option("--min", o.min, "box corner X Y")->required()->expected(2);
  semantic_slice_->add_option("--max", o.max, "box corner X Y")->required()->expected(2);
  semantic_slice_->add_option("--resolution", o.resolution, "cell size, metres")->capture_default_str();
  semantic_slice_->add_option("--out", o.out, "folder for distance.tiff (float metres) and distance.png (mm)")
      ->required();

  segment_check_ =
      app.add_subcommand("segment-check", "whether a sphere moved along straight segments stays clear of obstacles");
  segment_check_->add_option("--from", o.from, "start X Y Z (repeat with --to for more segments)")
      ->required()
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  segment_check_->add_option("--to", o.to, "end X Y Z")
      ->required()
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  segment_check_->add_option("--radius", o.radius, "sphere radius, metres (0: a point)")->capture_default_str();
  segment_check_->add_flag("--json", o.json, "print JSON");
}

bool DistanceCommands::parsed() const {
  return distance_->parsed() || occupancy_->parsed() || semantic_distance_->parsed() || semantic_slice_->parsed() ||
         segment_check_->parsed();
}

int DistanceCommands::run(client::MapClient& map, std::chrono::milliseconds timeout,
                          const std::function<const LabelLegend&()>& legend) const {
  if (distance_->parsed()) return distance(map, timeout);
  if (occupancy_->parsed()) return occupancy(map, timeout);
  if (semantic_distance_->parsed()) return semanticDistance(map, timeout, legend());
  if (semantic_slice_->parsed()) return semanticSlice(map, timeout, legend());
  if (segment_check_->parsed()) return segmentCheck(map, timeout);
  return cli::kExitUsage;
}

int DistanceCommands::distance(client::MapClient& map, std::chrono::milliseconds timeout) const {
  const auto points = triples(o_.points);
  auto samples = map.distances(points, timeout);
  if (!samples) return reportFailure(samples);
  std::ostringstream out;
  if (o_.json) out << "[";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& s = samples.value()[i];
    const auto& p = points[i];
    if (o_.json) {
      out << (i ? ",\n " : "") << "{\"point\": [" << p.x() << ", " << p.y() << ", " << p.z()
          << "], \"known\": " << (s.known ? "true" : "false") << ", \"beyond\": " << (s.beyond ? "true" : "false")
          << ", \"distance\": " << s.distance << ", \"gradient\": [" << s.gradient.x() << ", " << s.gradient.y() << ", "
          << s.gradient.z() << "]}";
    } else if (!s.known) {
      out << number(p.x()) << " " << number(p.y()) << " " << number(p.z()) << "  unknown\n";
    } else {
      out << number(p.x()) << " " << number(p.y()) << " " << number(p.z()) << "  distance " << number(s.distance)
          << (s.beyond ? " (beyond the maximum)" : "") << "  gradient " << number(s.gradient.x(), 2) << " "
          << number(s.gradient.y(), 2) << " " << number(s.gradient.z(), 2) << "\n";
    }
  }
  if (o_.json) out << "]\n";
  std::cout << out.str();
  return cli::kExitOk;
}

Status writeOccupancyMap(const client::OccupancyGrid& grid, const std::string& png_path) {
  cv::Mat image(static_cast<int>(grid.height), static_cast<int>(grid.width), CV_8UC1);
  for (uint32_t row = 0; row < grid.height; ++row)
    for (uint32_t col = 0; col < grid.width; ++col) {
      const int8_t cell = grid.cells[static_cast<std::size_t>(row) * grid.width + col];
      const uint8_t grey = cell == kOccupancyUnknown    ? 205
                           : cell == kOccupancyOccupied ? 0
                           : cell == kOccupancyFree     ? 254
                                                        : 100;  // inflated
      image.at<uint8_t>(static_cast<int>(grid.height - 1 - row), static_cast<int>(col)) = grey;
    }
  if (!cv::imwrite(png_path, image)) return makeError("cannot write " + png_path);
  const std::filesystem::path yaml = std::filesystem::path(png_path).replace_extension(".yaml");
  std::ofstream out(yaml);
  out << "image: " << std::filesystem::path(png_path).filename().string() << "\n"
      << "mode: trinary\n"
      << "resolution: " << grid.resolution << "\n"
      << "origin: [" << grid.origin.x() << ", " << grid.origin.y() << ", 0.0]\n"
      << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\n";
  if (!out) return makeError("cannot write " + yaml.string());
  return Status::Ok();
}

int DistanceCommands::occupancy(client::MapClient& map, std::chrono::milliseconds timeout) const {
  client::OccupancySliceRequest request;
  request.z_min = o_.z_min;
  request.z_max = o_.z_max;
  request.inflation_radius = o_.inflation;
  if (!o_.min.empty() || !o_.max.empty()) {
    if (o_.min.size() != 2 || o_.max.size() != 2) return usage("--min and --max take 2 numbers each, both or neither");
    request.use_bounds = true;
    request.min = {o_.min[0], o_.min[1]};
    request.max = {o_.max[0], o_.max[1]};
  }
  auto grid = map.occupancySlice(request, timeout);
  if (!grid) return reportFailure(grid);
  const auto& g = grid.value();
  if (g.cells.empty()) {
    spdlog::error("the map has no observed space to slice yet");
    return cli::kExitFailure;
  }
  if (Status written = writeOccupancyMap(g, o_.out); !written) {
    spdlog::error("{}", written.error());
    return cli::kExitFailure;
  }
  std::size_t counts[4] = {0, 0, 0, 0};  // free, inflated, occupied, unknown
  for (int8_t c : g.cells)
    ++counts[c == kOccupancyFree ? 0 : c == kOccupancyInflated ? 1 : c == kOccupancyOccupied ? 2 : 3];
  spdlog::info("{}: {}x{} cells of {} m from ({}, {}): {} free, {} inflated, {} occupied, {} unknown", o_.out, g.width,
               g.height, g.resolution, g.origin.x(), g.origin.y(), counts[0], counts[1], counts[2], counts[3]);
  std::cout << o_.out << "\n";
  return cli::kExitOk;
}

int DistanceCommands::semanticDistance(client::MapClient& map, std::chrono::milliseconds timeout,
                                       const LabelLegend& legend) const {
  auto labels = labelIds(o_.labels, legend);
  if (!labels) return usage(labels.error());
  const auto points = triples(o_.points);
  auto samples = map.semanticDistances(labels.value(), points, timeout);
  if (!samples) return reportFailure(samples);
  std::ostringstream out;
  if (o_.json) out << "[";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& s = samples.value()[i];
    const auto& p = points[i];
    if (o_.json) {
      out << (i ? ",\n " : "") << "{\"point\": [" << p.x() << ", " << p.y() << ", " << p.z()
          << "], \"found\": " << (s.found ? "true" : "false") << ", \"label\": " << s.label
          << ", \"distance\": " << s.distance << ", \"direction\": [" << s.direction.x() << ", " << s.direction.y()
          << ", " << s.direction.z() << "], \"surface_point\": [" << s.surface_point.x() << ", " << s.surface_point.y()
          << ", " << s.surface_point.z() << "]}";
    } else if (!s.found) {
      out << number(p.x()) << " " << number(p.y()) << " " << number(p.z()) << "  no such surface in the map\n";
    } else {
      out << number(p.x()) << " " << number(p.y()) << " " << number(p.z()) << "  " << labelName(legend, s.label)
          << " at " << number(s.distance) << " m, towards " << number(s.direction.x(), 2) << " "
          << number(s.direction.y(), 2) << " " << number(s.direction.z(), 2) << "\n";
    }
  }
  if (o_.json) out << "]\n";
  std::cout << out.str();
  return cli::kExitOk;
}

int DistanceCommands::semanticSlice(client::MapClient& map, std::chrono::milliseconds timeout,
                                    const LabelLegend& legend) const {
  auto labels = labelIds(o_.labels, legend);
  if (!labels) return usage(labels.error());
  client::SemanticSliceRequest request;
  request.labels = labels.value();
  request.z = o_.z;
  request.min = {o_.min[0], o_.min[1]};
  request.max = {o_.max[0], o_.max[1]};
  request.resolution = o_.resolution;
  auto slice = map.semanticSlice(request, timeout);
  if (!slice) return reportFailure(slice);
  const cv::Mat& distance = slice.value().distance;
  std::filesystem::create_directories(o_.out);
  const std::filesystem::path folder(o_.out);
  // Rows flipped so that the top of the image is the largest y, as a map is looked at.
  cv::Mat flipped;
  cv::flip(distance, flipped, 0);
  cv::Mat millimetres(flipped.size(), CV_16UC1);
  for (int r = 0; r < flipped.rows; ++r)
    for (int c = 0; c < flipped.cols; ++c) {
      const float d = flipped.at<float>(r, c);
      millimetres.at<uint16_t>(r, c) =
          static_cast<uint16_t>(std::isfinite(d) ? std::min(65535.0f, std::round(d * 1000.0f)) : 65535.0f);
    }
  if (!cv::imwrite((folder / "distance.tiff").string(), flipped) ||
      !cv::imwrite((folder / "distance.png").string(), millimetres)) {
    spdlog::error("cannot write into {}", o_.out);
    return cli::kExitFailure;
  }
  double lo = 0, hi = 0;
  cv::minMaxLoc(distance, &lo, &hi);
  spdlog::info("{}x{} cells of {} m at z {}: distances {:.3f}..{:.3f} m", distance.cols, distance.rows,
               slice.value().resolution, slice.value().z, lo, hi);
  std::cout << (folder / "distance.tiff").string() << "\n" << (folder / "distance.png").string() << "\n";
  return cli::kExitOk;
}

int DistanceCommands::segmentCheck(client::MapClient& map, std::chrono::milliseconds timeout) const {
  const auto from = triples(o_.from), to = triples(o_.to);
  if (from.size() != to.size()) return usage("give as many --to as --from");
  std::vector<client::Segment> segments;
  for (std::size_t i = 0; i < from.size(); ++i) segments.push_back({from[i], to[i]});
  auto results = map.checkSegments(segments, o_.radius, timeout);
  if (!results) return reportFailure(results);
  std::ostringstream out;
  if (o_.json) out << "[";
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto& r = results.value()[i];
    if (o_.json) {
      out << (i ? ",\n " : "") << "{\"status\": \"" << statusName(r.status) << "\", \"fraction\": " << r.fraction
          << ", \"blocked_at\": [" << r.blocked_at.x() << ", " << r.blocked_at.y() << ", " << r.blocked_at.z()
          << "], \"min_clearance\": " << r.min_clearance << "}";
    } else {
      out << "segment " << i << ": " << statusName(r.status);
      if (r.status != client::SegmentStatus::kFree)
        out << " at " << number(r.fraction, 2) << " of its length (" << number(r.blocked_at.x()) << " "
            << number(r.blocked_at.y()) << " " << number(r.blocked_at.z()) << ")";
      out << ", least clearance " << number(r.min_clearance) << " m\n";
    }
  }
  if (o_.json) out << "]\n";
  std::cout << out.str();
  return cli::kExitOk;
}

}  // namespace semfuse::tools
