#include "semfuse/core/camera_check.hpp"

#include <cmath>
#include <string>

#include "semfuse/core/number_text.hpp"

namespace semfuse {

Status checkProjection(const PinholeIntrinsics& k) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(k.fx) || !positive(k.fy))
    return invalidArgument("intrinsics: focal lengths must be finite and > 0, got fx=" + numberText(k.fx) +
                           " fy=" + numberText(k.fy));
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    return invalidArgument("intrinsics: principal point must be finite, got cx=" + numberText(k.cx) +
                           " cy=" + numberText(k.cy));
  return Status::Ok();
}

Status checkIntrinsics(const PinholeIntrinsics& k, int max_side) {
  const std::string size = std::to_string(k.width) + "x" + std::to_string(k.height);
  if (k.width <= 0 || k.height <= 0) return invalidArgument("intrinsics: image size " + size + " is empty");
  if (k.width > max_side || k.height > max_side)
    return invalidArgument("intrinsics: image size " + size + " exceeds the " + std::to_string(max_side) +
                           "-pixel limit");
  return checkProjection(k);
}

Status checkRigidPose(const Pose& pose, double tolerance) {
  const Eigen::Matrix4d& m = pose.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(m(r, c)))
        return invalidArgument("pose: non-finite value " + numberText(m(r, c)) + " at row " + std::to_string(r) +
                               ", column " + std::to_string(c));
  if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0)
    return invalidArgument("pose: bottom row must be [0 0 0 1], got [" + numberText(m(3, 0)) + " " +
                           numberText(m(3, 1)) + " " + numberText(m(3, 2)) + " " + numberText(m(3, 3)) + "]");
  const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
  const double error = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm();
  if (error > tolerance)
    return invalidArgument("pose: rotation is not orthonormal (|R^T R - I| = " + numberText(error) + ", tolerance " +
                           numberText(tolerance) + ")");
  const double det = rotation.determinant();
  if (det < 0.0) return invalidArgument("pose: rotation is a reflection (determinant " + numberText(det) + ")");
  return Status::Ok();
}

Status checkCamera(const PinholeIntrinsics& intrinsics, const Pose& camera_to_world, int max_side) {
  if (Status s = checkIntrinsics(intrinsics, max_side); !s) return s;
  return checkRigidPose(camera_to_world);
}

}  // namespace semfuse
