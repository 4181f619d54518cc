#include "trajectory_file.hpp"

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "semfuse/client/server_status.hpp"

namespace semfuse::tools {

std::optional<TrajectoryFormat> trajectoryFormatNamed(const std::string& name) {
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "csv") return TrajectoryFormat::kCsv;
  return std::nullopt;
}

std::string trajectoryHeader(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum:
      return "# timestamp tx ty tz qx qy qz qw (camera-to-world, seconds of the frame's stamp)\n";
    case TrajectoryFormat::kKitti:
      return "";
    case TrajectoryFormat::kCsv:
      return "camera_id,seq,stamp,state,posed,tx,ty,tz,qx,qy,qz,qw,inlier_ratio,residual_m,iterations,track_ms\n";
  }
  return "";
}

std::string trajectoryLine(const TrackedPose& pose, TrajectoryFormat format) {
  const Pose& m = pose.camera_to_world;
  const Eigen::Vector3d t = m.translation();
  const Eigen::Quaterniond q(m.linear());
  // Nanosecond stamps need 9 decimals; TUM's own files have 4-6, and its tools read any.
  const std::string stamp = fmt::format("{}.{:09d}", pose.stamp.sec, pose.stamp.nanosec);
  switch (format) {
    case TrajectoryFormat::kTum:
      return fmt::format("{} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", stamp, t.x(), t.y(), t.z(), q.x(),
                         q.y(), q.z(), q.w());
    case TrajectoryFormat::kKitti: {
      std::string line;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) line += fmt::format("{}{:.9g}", line.empty() ? "" : " ", m.matrix()(r, c));
      return line + "\n";
    }
    case TrajectoryFormat::kCsv:
      return fmt::format("{},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f},{:.4f},{:.6f},{},{:.3f}\n",
                         pose.camera_id, pose.seq, stamp, client::trackingStateName(static_cast<uint8_t>(pose.state)),
                         pose.posed ? 1 : 0, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(), pose.inlier_ratio,
                         pose.residual, pose.iterations, pose.track_ms);
  }
  return "";
}

}  // namespace semfuse::tools
