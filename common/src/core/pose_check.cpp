#include "semfuse/core/pose_check.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace semfuse {
namespace {
std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}
}  // namespace

Status checkRigidPose(const Pose& pose, double tolerance) {
  const Eigen::Matrix<double, 3, 4> m = pose.matrix().topRows<3>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(m(r, c)))
        return makeError("pose: non-finite value " + number(m(r, c)) + " at row " + std::to_string(r) + ", column " +
                         std::to_string(c));
  const Eigen::Matrix3d rotation = m.leftCols<3>();
  const double error = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm();
  if (error > tolerance)
    return makeError("pose: rotation is not orthonormal (|R^T R - I| = " + number(error) + ", tolerance " +
                     number(tolerance) + ")");
  const double det = rotation.determinant();
  if (det < 0.0) return makeError("pose: rotation is a reflection (determinant " + number(det) + ")");
  return Status::Ok();
}

}  // namespace semfuse
