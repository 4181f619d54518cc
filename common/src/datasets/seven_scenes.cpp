#include "semfuse/datasets/seven_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "image_files.hpp"
#include "semfuse/core/camera_check.hpp"
#include "text_matrix.hpp"

namespace semfuse::datasets {
namespace fs = std::filesystem;

namespace {

constexpr double kMillimetre = 0.001;

// "frame-000123.depth.png" -> 123; nullopt for any other name.
std::optional<uint64_t> frameNumberOf(const std::string& name) {
  static const std::string prefix = "frame-", suffix = ".depth.png";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return std::nullopt;
  }
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  const bool all_digits = std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (digits.empty() || digits.size() > 18 || !all_digits) return std::nullopt;
  return std::stoull(digits);
}

std::string frameStem(uint64_t number) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "frame-%06llu", static_cast<unsigned long long>(number));
  return buffer;
}

}  // namespace

Result<PinholeIntrinsics> readSevenScenesIntrinsics(const fs::path& file) {
  auto numbers = detail::readNumbers(file, 9, "camera intrinsics");
  if (!numbers) return makeError(numbers.error());
  const std::vector<double>& k = numbers.value();
  PinholeIntrinsics intrinsics;
  intrinsics.fx = k[0];
  intrinsics.fy = k[4];
  intrinsics.cx = k[2];
  intrinsics.cy = k[5];
  // The file holds K alone: the image size comes from the images (SevenScenesReader::open).
  if (Status s = checkProjection(intrinsics); !s) return s.errorInfo().prefixed(file.string() + ": ");
  return intrinsics;
}

Result<Pose> readSevenScenesPose(const fs::path& file) {
  auto numbers = detail::readNumbers(file, 16, "pose");
  if (!numbers) return makeError(numbers.error());
  const std::vector<double>& m = numbers.value();
  constexpr double kTolerance = 1e-6;
  if (std::abs(m[12]) > kTolerance || std::abs(m[13]) > kTolerance || std::abs(m[14]) > kTolerance ||
      std::abs(m[15] - 1.0) > kTolerance) {
    return makeError("pose " + file.string() + ": last row is not 0 0 0 1");
  }
  Pose pose = Pose::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = m[static_cast<std::size_t>(r * 4 + c)];
  }
  if (Status s = checkRigidPose(pose); !s) return s.errorInfo().prefixed(file.string() + ": ");
  return pose;
}

Result<SevenScenesReader> SevenScenesReader::open(const fs::path& folder, SevenScenesOptions options) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return makeError("7-Scenes folder not found: " + folder.string());

  SevenScenesReader reader;
  reader.folder_ = folder;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, ec)) {
    if (auto number = frameNumberOf(entry.path().filename().string())) reader.frame_numbers_.push_back(*number);
  }
  if (ec) return makeError("cannot list 7-Scenes folder " + folder.string() + ": " + ec.message());
  if (reader.frame_numbers_.empty()) {
    return makeError("no frame-NNNNNN.depth.png files in 7-Scenes folder " + folder.string());
  }
  std::sort(reader.frame_numbers_.begin(), reader.frame_numbers_.end());

  if (options.intrinsics) {
    reader.intrinsics_ = *options.intrinsics;
  } else {
    auto intrinsics = readSevenScenesIntrinsics(folder / "camera-intrinsics.txt");
    if (!intrinsics) return makeError(intrinsics.error());
    reader.intrinsics_ = intrinsics.value();
  }
  if (reader.intrinsics_.width <= 0 || reader.intrinsics_.height <= 0) {
    auto size = detail::readImageSize(reader.depthPath(0));
    if (!size) return makeError(size.error());
    reader.intrinsics_.width = size.value().width;
    reader.intrinsics_.height = size.value().height;
  }
  if (Status s = checkIntrinsics(reader.intrinsics_); !s) return s.errorInfo().prefixed("7-Scenes ");
  reader.options_ = std::move(options);
  return reader;
}

fs::path SevenScenesReader::depthPath(std::size_t index) const {
  return folder_ / (frameStem(frameNumber(index)) + ".depth.png");
}
fs::path SevenScenesReader::colorPath(std::size_t index) const {
  return folder_ / (frameStem(frameNumber(index)) + ".color.jpg");
}
fs::path SevenScenesReader::posePath(std::size_t index) const {
  return folder_ / (frameStem(frameNumber(index)) + ".pose.txt");
}

Result<Frame> SevenScenesReader::load(std::size_t index) const { return loadFrame(index, true); }
Result<Frame> SevenScenesReader::loadDepthOnly(std::size_t index) const { return loadFrame(index, false); }

Result<Frame> SevenScenesReader::loadFrame(std::size_t index, bool with_color) const {
  if (index >= count()) {
    return makeError("7-Scenes frame index " + std::to_string(index) + " out of range (" + std::to_string(count()) +
                     " frames)");
  }
  Frame frame;
  frame.camera_id = options_.camera_id;
  frame.seq = frameNumber(index);
  if (options_.nominal_rate_hz > 0.0) {
    frame.stamp = detail::stampFromSeconds(static_cast<double>(frame.seq) / options_.nominal_rate_hz);
  }
  frame.intrinsics = intrinsics_;

  auto depth = detail::readDepthAsMetres(depthPath(index), kMillimetre, /*saturated_is_invalid=*/true);
  if (!depth) return makeError(depth.error());
  frame.depth = std::move(depth).value();
  if (frame.depth.cols != intrinsics_.width || frame.depth.rows != intrinsics_.height) {
    return makeError("depth image " + depthPath(index).string() + " is " + std::to_string(frame.depth.cols) + "x" +
                     std::to_string(frame.depth.rows) + ", the sequence's first frame is " +
                     std::to_string(intrinsics_.width) + "x" + std::to_string(intrinsics_.height));
  }

  if (with_color) {
    auto color = detail::readColorAsRgb(colorPath(index));
    if (!color) return makeError(color.error());
    frame.color = std::move(color).value();
    if (frame.color.size() != frame.depth.size()) {
      return makeError("colour image " + colorPath(index).string() + " is " + std::to_string(frame.color.cols) + "x" +
                       std::to_string(frame.color.rows) + ", depth is " + std::to_string(frame.depth.cols) + "x" +
                       std::to_string(frame.depth.rows));
    }
  }

  std::error_code ec;
  if (fs::exists(posePath(index), ec)) {
    auto pose = readSevenScenesPose(posePath(index));
    if (!pose) return makeError(pose.error());
    frame.camera_to_world = pose.value();
  }
  return frame;
}

}  // namespace semfuse::datasets
