#include "semfuse/datasets/tum_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "semfuse/core/camera_check.hpp"
#include "tum_lines.hpp"

namespace semfuse::datasets {
namespace fs = std::filesystem;

Result<std::vector<TimedPose>> readTumTrajectory(const fs::path& file) {
  auto lines = tumDataLines(file);
  if (!lines) return makeError(lines.error());
  std::vector<TimedPose> poses;
  for (const auto& [number, text] : lines.value()) {
    std::istringstream parse(text);
    double t = 0, tx = 0, ty = 0, tz = 0, qx = 0, qy = 0, qz = 0, qw = 0;
    if (!(parse >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw) || !std::isfinite(t))
      return tumLineError(file, number, "expected 'timestamp tx ty tz qx qy qz qw', got '" + text + "'");
    const Eigen::Quaterniond q(qw, qx, qy, qz);
    const double norm = q.norm();
    if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3)
      return tumLineError(file, number, "quaternion norm " + std::to_string(norm) + " is not 1");
    TimedPose sample;
    sample.time = t;
    sample.pose.linear() = q.normalized().toRotationMatrix();
    sample.pose.translation() = Eigen::Vector3d(tx, ty, tz);
    if (Status s = checkRigidPose(sample.pose); !s) return tumLineError(file, number, s.error());
    poses.push_back(sample);
  }
  std::sort(poses.begin(), poses.end(), [](const TimedPose& a, const TimedPose& b) { return a.time < b.time; });
  return poses;
}

std::optional<Pose> trajectoryPoseAt(const std::vector<TimedPose>& sorted, double time, double window) {
  const auto after = std::lower_bound(sorted.begin(), sorted.end(), time,
                                      [](const TimedPose& item, double t) { return item.time < t; });
  if (after != sorted.end() && after != sorted.begin()) {
    const TimedPose& before = *std::prev(after);
    if (time - before.time <= window && after->time - time <= window && after->time > before.time) {
      const double f = (time - before.time) / (after->time - before.time);
      const Eigen::Quaterniond q0(before.pose.linear()), q1(after->pose.linear());
      Pose pose = Pose::Identity();
      pose.linear() = q0.slerp(f, q1).normalized().toRotationMatrix();
      pose.translation() = (1.0 - f) * before.pose.translation() + f * after->pose.translation();
      return pose;
    }
  }
  // The nearest sample within the window.
  const TimedPose* nearest = nullptr;
  double gap = window;
  for (auto it : {after, after == sorted.begin() ? sorted.end() : std::prev(after)}) {
    if (it == sorted.end() || std::abs(it->time - time) > gap) continue;
    gap = std::abs(it->time - time);
    nearest = &*it;
  }
  return nearest ? std::optional<Pose>(nearest->pose) : std::nullopt;
}

}  // namespace semfuse::datasets
