#pragma once
// Exponential map of se(3). The tracker parameterises a pose update as a twist xi = (v, w)
// (translation part first) applied on the left, T <- exp(xi) * T, so that the Jacobian of a
// world-frame residual is taken at the transformed point (Bylow et al., RSS 2013, Sec. III).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace semfuse::tracking {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// exp(xi) for xi = (v, w): rotation exp([w]x), translation V(w) v with the left Jacobian V of
// SO(3), exact for any angle (the series form is used near zero to avoid 0/0).
Eigen::Isometry3d expSE3(const Vector6d& xi);

// The rigid transform nearest to `pose` (rotation projected onto SO(3) by SVD). Poses from files
// (7-Scenes stores 4x4 matrices with ~1e-3 of non-orthogonality) and long products of updates
// drift off SO(3); integrators and inverses assume they do not.
Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& pose);

// Rotation angle of a rotation matrix (radians, in [0, pi]), robust to rounding near 0 and pi.
double rotationAngle(const Eigen::Matrix3d& rotation);

}  // namespace semfuse::tracking
