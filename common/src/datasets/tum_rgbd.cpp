#include "semfuse/datasets/tum_rgbd.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "image_files.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/datasets/tum_trajectory.hpp"
#include "tum_lines.hpp"

namespace semfuse::datasets {
namespace fs = std::filesystem;

namespace {

struct TimedFile {
  double time = 0.0;
  fs::path file;
};

// rgb.txt / depth.txt: "timestamp filename", sorted by time.
Result<std::vector<TimedFile>> readFileList(const fs::path& file) {
  auto lines = tumDataLines(file);
  if (!lines) return makeError(lines.error());
  std::vector<TimedFile> list;
  for (const auto& [number, text] : lines.value()) {
    std::istringstream parse(text);
    TimedFile entry;
    std::string name;
    if (!(parse >> entry.time >> name) || !std::isfinite(entry.time)) {
      return tumLineError(file, number, "expected 'timestamp filename', got '" + text + "'");
    }
    entry.file = name;
    list.push_back(std::move(entry));
  }
  if (list.empty()) return makeError("TUM list has no entries: " + file.string());
  std::sort(list.begin(), list.end(), [](const TimedFile& a, const TimedFile& b) { return a.time < b.time; });
  return list;
}

// Index of the element of a time-sorted list nearest to `time`, if within `window` seconds.
template <typename T>
std::optional<std::size_t> nearestInTime(const std::vector<T>& sorted, double time, double window) {
  auto after =
      std::lower_bound(sorted.begin(), sorted.end(), time, [](const T& item, double t) { return item.time < t; });
  std::optional<std::size_t> best;
  double best_gap = window;
  auto consider = [&](typename std::vector<T>::const_iterator it) {
    const double gap = std::abs(it->time - time);
    if (gap <= best_gap) {
      best_gap = gap;
      best = static_cast<std::size_t>(it - sorted.begin());
    }
  };
  if (after != sorted.end()) consider(after);
  if (after != sorted.begin()) consider(std::prev(after));
  return best;
}

}  // namespace

std::optional<PinholeIntrinsics> tumFreiburgIntrinsics(int freiburg_number) {
  // Published on the TUM RGB-D benchmark's "file formats" page (depth camera, 640x480).
  switch (freiburg_number) {
    case 1:
      return PinholeIntrinsics{640, 480, 517.3, 516.5, 318.6, 255.3};
    case 2:
      return PinholeIntrinsics{640, 480, 520.9, 521.0, 325.1, 249.7};
    case 3:
      return PinholeIntrinsics{640, 480, 535.4, 539.2, 320.1, 247.6};
    default:
      return std::nullopt;
  }
}

std::optional<int> tumFreiburgNumberFromName(const std::string& folder_name) {
  static const std::regex pattern("freiburg([123])");
  std::smatch match;
  if (!std::regex_search(folder_name, match, pattern)) return std::nullopt;
  return std::stoi(match[1].str());
}

Result<TumRgbdReader> TumRgbdReader::open(const fs::path& folder, TumRgbdOptions options) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return makeError("TUM RGB-D folder not found: " + folder.string());

  TumRgbdReader reader;
  reader.folder_ = folder;
  if (options.intrinsics) {
    reader.intrinsics_ = *options.intrinsics;
  } else {
    // fs::path("a/b/").filename() is empty; canonical form gives the real folder name.
    const std::string name = fs::weakly_canonical(folder, ec).filename().string();
    const auto number = tumFreiburgNumberFromName(name);
    if (!number) {
      return makeError("cannot tell the TUM camera from folder name '" + name +
                       "' (expected freiburg1, freiburg2 or freiburg3 in it): give the intrinsics");
    }
    reader.intrinsics_ = *tumFreiburgIntrinsics(*number);
  }
  if (Status s = checkIntrinsics(reader.intrinsics_); !s) return s.errorInfo().prefixed("TUM RGB-D ");

  auto depth_list = readFileList(folder / "depth.txt");
  if (!depth_list) return makeError(depth_list.error());
  auto color_list = readFileList(folder / "rgb.txt");
  if (!color_list) return makeError(color_list.error());
  std::vector<TimedPose> poses;
  if (fs::exists(folder / "groundtruth.txt", ec)) {
    auto ground_truth = readTumTrajectory(folder / "groundtruth.txt");
    if (!ground_truth) return makeError(ground_truth.error());
    poses = std::move(ground_truth).value();
  }

  const double window = options.max_time_difference_s;
  for (const TimedFile& depth : depth_list.value()) {
    const auto color_index = nearestInTime(color_list.value(), depth.time, window);
    if (!color_index) continue;
    const TimedFile& color = color_list.value()[*color_index];
    Entry entry{depth.time, depth.file, color.time, color.file, std::nullopt};
    entry.camera_to_world = trajectoryPoseAt(poses, depth.time, window);
    reader.entries_.push_back(std::move(entry));
  }
  if (reader.entries_.empty()) {
    return makeError("TUM folder " + folder.string() + ": no depth image has a colour image within " +
                     std::to_string(window * 1000.0) + " ms");
  }
  reader.options_ = std::move(options);
  return reader;
}

Result<Frame> TumRgbdReader::load(std::size_t index) const { return loadFrame(index, true); }
Result<Frame> TumRgbdReader::loadDepthOnly(std::size_t index) const { return loadFrame(index, false); }

Result<Frame> TumRgbdReader::loadFrame(std::size_t index, bool with_color) const {
  if (index >= count()) {
    return makeError("TUM frame index " + std::to_string(index) + " out of range (" + std::to_string(count()) +
                     " frames)");
  }
  const Entry& source = entries_[index];
  Frame frame;
  frame.camera_id = options_.camera_id;
  frame.seq = index;
  frame.stamp = detail::stampFromSeconds(source.depth_time);
  frame.intrinsics = intrinsics_;
  frame.camera_to_world = source.camera_to_world;

  auto depth = detail::readDepthAsMetres(folder_ / source.depth_file, 1.0 / options_.depth_units_per_metre,
                                         /*saturated_is_invalid=*/false);
  if (!depth) return makeError(depth.error());
  frame.depth = std::move(depth).value();
  if (frame.depth.cols != intrinsics_.width || frame.depth.rows != intrinsics_.height) {
    return makeError("depth image " + (folder_ / source.depth_file).string() + " is " +
                     std::to_string(frame.depth.cols) + "x" + std::to_string(frame.depth.rows) +
                     ", the intrinsics are for " + std::to_string(intrinsics_.width) + "x" +
                     std::to_string(intrinsics_.height));
  }
  if (with_color) {
    auto color = detail::readColorAsRgb(folder_ / source.color_file);
    if (!color) return makeError(color.error());
    frame.color = std::move(color).value();
    if (frame.color.size() != frame.depth.size()) {
      return makeError("colour image " + (folder_ / source.color_file).string() + " is " +
                       std::to_string(frame.color.cols) + "x" + std::to_string(frame.color.rows) + ", depth is " +
                       std::to_string(frame.depth.cols) + "x" + std::to_string(frame.depth.rows));
    }
  }
  return frame;
}

}  // namespace semfuse::datasets
