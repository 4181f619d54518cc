#pragma once
// Reader of a Microsoft 7-Scenes sequence folder:
//   camera-intrinsics.txt      3x3 K (fx 0 cx / 0 fy cy / 0 0 1), optional when intrinsics are given
//   frame-NNNNNN.depth.png     16-bit depth in millimetres; 0 and 65535 mark invalid pixels
//   frame-NNNNNN.color.jpg     colour image (not registered to the depth, a property of the dataset)
//   frame-NNNNNN.pose.txt      4x4 camera-to-world, metres (optional: a frame without one has no pose)
// Frames are indexed 0..count()-1 in order of their frame number; gaps in the numbering are fine.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::datasets {

struct SevenScenesOptions {
  std::string camera_id = "7scenes";
  // Overrides camera-intrinsics.txt (width/height are still taken from the first depth image
  // when left at 0).
  std::optional<PinholeIntrinsics> intrinsics;
  // 7-Scenes has no time stamps; frame n is stamped n / nominal_rate_hz seconds (Kinect v1: 30 Hz).
  double nominal_rate_hz = 30.0;
};

class SevenScenesReader {
 public:
  // Scans the folder; fails when it holds no frames or the intrinsics are missing or malformed.
  static Result<SevenScenesReader> open(const std::filesystem::path& folder, SevenScenesOptions options = {});

  std::size_t count() const { return frame_numbers_.size(); }
  const PinholeIntrinsics& intrinsics() const { return intrinsics_; }
  const std::filesystem::path& folder() const { return folder_; }
  // The NNNNNN of frame `index` (also used as Frame::seq).
  uint64_t frameNumber(std::size_t index) const { return frame_numbers_.at(index); }

  // Depth (CV_32FC1 metres, invalid = 0), colour (CV_8UC3 RGB) and pose when the folder has one.
  Result<Frame> load(std::size_t index) const;
  // Same without decoding the colour JPEG (about half the time of load()); Frame::color is empty.
  Result<Frame> loadDepthOnly(std::size_t index) const;

  std::filesystem::path depthPath(std::size_t index) const;
  std::filesystem::path colorPath(std::size_t index) const;
  std::filesystem::path posePath(std::size_t index) const;

 private:
  SevenScenesReader() = default;
  Result<Frame> loadFrame(std::size_t index, bool with_color) const;

  std::filesystem::path folder_;
  SevenScenesOptions options_;
  PinholeIntrinsics intrinsics_;
  std::vector<uint64_t> frame_numbers_;
};

// Parses camera-intrinsics.txt (3x3 K); width and height are left 0. The projection passes
// semfuse/core/camera_check.hpp's checkProjection.
Result<PinholeIntrinsics> readSevenScenesIntrinsics(const std::filesystem::path& file);
// Parses a frame-NNNNNN.pose.txt (4x4 row-major, last row 0 0 0 1); the pose passes checkRigidPose.
Result<Pose> readSevenScenesPose(const std::filesystem::path& file);

}  // namespace semfuse::datasets
