#pragma once
// Reader of a TUM RGB-D benchmark sequence folder (e.g. rgbd_dataset_freiburg1_xyz/):
//   rgb.txt, depth.txt         "timestamp relative/path.png" per line, '#' comments
//   groundtruth.txt            "timestamp tx ty tz qx qy qz qw" (camera-to-world), optional
//   depth/*.png                16-bit, 5000 units per metre, 0 = invalid
// Each depth image is paired with the colour image nearest in time, within max_time_difference_s;
// a depth image without such a partner is skipped (as TUM's associate.py does). The pose is the
// ground truth interpolated to the depth image's time stamp from the samples on either side
// within the same window (or the nearest sample within it, or none).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::datasets {

struct TumRgbdOptions {
  std::string camera_id = "tum";
  // When absent, taken from "freiburg1/2/3" in the folder name (TUM's calibrated values).
  std::optional<PinholeIntrinsics> intrinsics;
  double max_time_difference_s = 0.02;
  double depth_units_per_metre = 5000.0;
};

// TUM's published calibration of the freiburg 1, 2 and 3 Kinects (640x480); nullopt for others.
std::optional<PinholeIntrinsics> tumFreiburgIntrinsics(int freiburg_number);
// The freiburg camera named by a folder such as "rgbd_dataset_freiburg2_desk", or nullopt.
std::optional<int> tumFreiburgNumberFromName(const std::string& folder_name);

class TumRgbdReader {
 public:
  struct Entry {
    double depth_time = 0.0;
    std::filesystem::path depth_file;  // relative to the folder
    double color_time = 0.0;
    std::filesystem::path color_file;
    std::optional<Pose> camera_to_world;
  };

  static Result<TumRgbdReader> open(const std::filesystem::path& folder, TumRgbdOptions options = {});

  std::size_t count() const { return entries_.size(); }
  const PinholeIntrinsics& intrinsics() const { return intrinsics_; }
  const Entry& entry(std::size_t index) const { return entries_.at(index); }

  // Frame::seq = index, stamp = the depth image's time stamp.
  Result<Frame> load(std::size_t index) const;
  Result<Frame> loadDepthOnly(std::size_t index) const;

 private:
  TumRgbdReader() = default;
  Result<Frame> loadFrame(std::size_t index, bool with_color) const;

  std::filesystem::path folder_;
  TumRgbdOptions options_;
  PinholeIntrinsics intrinsics_;
  std::vector<Entry> entries_;
};

}  // namespace semfuse::datasets
