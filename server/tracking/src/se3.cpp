#include "semfuse/tracking/se3.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

namespace semfuse::tracking {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}
}  // namespace

Eigen::Isometry3d expSE3(const Vector6d& xi) {
  const Eigen::Vector3d v = xi.head<3>();
  const Eigen::Vector3d w = xi.tail<3>();
  const double theta = w.norm();
  const Eigen::Matrix3d W = skew(w);
  // Coefficients of V = I + a W + b W^2; Taylor series below 1e-5 rad, where the closed forms
  // lose all their digits to cancellation.
  double a = 0.5;
  double b = 1.0 / 6.0;
  if (theta > 1e-5) {
    const double t2 = theta * theta;
    a = (1.0 - std::cos(theta)) / t2;
    b = (theta - std::sin(theta)) / (t2 * theta);
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = theta > 0.0 ? Eigen::AngleAxisd(theta, w / theta).toRotationMatrix() : Eigen::Matrix3d::Identity();
  T.translation() = (Eigen::Matrix3d::Identity() + a * W + b * W * W) * v;
  return T;
}

Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& pose) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(pose.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) *= -1.0;  // a rotation, not a reflection
  Eigen::Isometry3d out = pose;
  out.linear() = u * svd.matrixV().transpose();
  return out;
}

double rotationAngle(const Eigen::Matrix3d& rotation) {
  // acos of the trace is ill-conditioned near 0; atan2 of the sine (from the skew part) and the
  // cosine (from the trace) is accurate everywhere.
  const double cos_angle = 0.5 * (rotation.trace() - 1.0);
  const Eigen::Vector3d axis_sin(rotation(2, 1) - rotation(1, 2), rotation(0, 2) - rotation(2, 0),
                                 rotation(1, 0) - rotation(0, 1));
  return std::atan2(0.5 * axis_sin.norm(), std::clamp(cos_angle, -1.0, 1.0));
}

}  // namespace semfuse::tracking
