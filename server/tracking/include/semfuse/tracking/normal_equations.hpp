#pragma once
// Gauss-Newton normal equations of a 6-DoF alignment, accumulated point by point: the upper
// triangle of J^T W J (21 values) and J^T W r (6 values) in double precision, so that summing
// tens of thousands of float Jacobians in any order (parallel reduction) loses no digits.
#include <array>
#include <cstddef>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {

struct NormalEquations {
  std::array<double, 21> jtj{};  // row-major upper triangle of J^T W J
  std::array<double, 6> jtr{};   // J^T W r
  double weighted_cost = 0.0;    // sum of w r^2
  std::size_t residuals = 0;     // points that contributed
  std::size_t observed = 0;      // points that landed where the field was observed (any |D|)
  std::size_t inliers = 0;       // points with |r| below the inlier threshold
  double inlier_sq_sum = 0.0;    // sum of r^2 over inliers

  void add(const Eigen::Matrix<float, 6, 1>& jacobian, float residual, float weight) {
    const Eigen::Matrix<double, 6, 1> j = jacobian.cast<double>();
    const double w = weight;
    std::size_t k = 0;
    for (int r = 0; r < 6; ++r) {
      const double wj = w * j[r];
      for (int c = r; c < 6; ++c) jtj[k++] += wj * j[c];
      jtr[static_cast<std::size_t>(r)] += wj * residual;
    }
    weighted_cost += w * static_cast<double>(residual) * residual;
    ++residuals;
  }

  void join(const NormalEquations& other) {
    for (std::size_t k = 0; k < jtj.size(); ++k) jtj[k] += other.jtj[k];
    for (std::size_t k = 0; k < jtr.size(); ++k) jtr[k] += other.jtr[k];
    weighted_cost += other.weighted_cost;
    residuals += other.residuals;
    observed += other.observed;
    inliers += other.inliers;
    inlier_sq_sum += other.inlier_sq_sum;
  }

  Matrix6d hessian() const {
    Matrix6d h;
    std::size_t k = 0;
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c) h(r, c) = h(c, r) = jtj[k++];
    return h;
  }

  Vector6d gradient() const { return Eigen::Map<const Vector6d>(jtr.data()); }
};

// Rotational columns of a pose Jacobian are (q x grad), metres times the translational ones;
// scaling them by 1 / length (the mean scene depth) makes the eigenvalues of both blocks
// comparable, so that conditioning measures missing constraints rather than units.
inline Vector6d depthScaling(double length) {
  Vector6d scale;
  scale << 1.0, 1.0, 1.0, 1.0 / length, 1.0 / length, 1.0 / length;
  return scale;
}

// The directions (in depth-scaled coordinates) that `conditioning` constrains: eigenvectors with
// more than rcond x its largest eigenvalue, as columns.
inline Eigen::Matrix<double, 6, Eigen::Dynamic> constrainedDirections(const Matrix6d& conditioning, double length,
                                                                      double rcond) {
  const Vector6d scale = depthScaling(length);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(scale.asDiagonal() * conditioning * scale.asDiagonal());
  const double largest = eigen.eigenvalues()(5);
  int count = 0;
  for (int k = 0; k < 6; ++k) count += largest > 0.0 && eigen.eigenvalues()(k) > rcond * largest;
  Eigen::Matrix<double, 6, Eigen::Dynamic> directions(6, count);
  for (int k = 6 - count, c = 0; k < 6; ++k, ++c) directions.col(c) = eigen.eigenvectors().col(k);
  return directions;
}

// Each term's normal matrix divided by its largest depth-scaled eigenvalue, summed: a direction
// is well conditioned here when any one term constrains it well for that term, however much
// stronger the other term is overall (colour gradients are tens of times depth gradients).
inline Matrix6d balancedConditioning(const Matrix6d& a, const Matrix6d& b, double length) {
  const Vector6d scale = depthScaling(length);
  auto normalised = [&](const Matrix6d& m) -> Matrix6d {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(scale.asDiagonal() * m * scale.asDiagonal(),
                                                        Eigen::EigenvaluesOnly);
    const double largest = eigen.eigenvalues()(5);
    return largest > 0.0 ? Matrix6d(m / largest) : Matrix6d(Matrix6d::Zero());
  };
  return normalised(a) + normalised(b);
}

// Gauss-Newton step of hessian x = -gradient restricted to the directions `conditioning`
// constrains (see constrainedDirections): along the others the pose keeps its starting value.
// `constrained` receives how many directions were solved for.
inline Vector6d constrainedStep(const Matrix6d& hessian, const Vector6d& gradient, const Matrix6d& conditioning,
                                double length, double rcond, double damping, int& constrained) {
  const Vector6d scale = depthScaling(length);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> basis = constrainedDirections(conditioning, length, rcond);
  constrained = static_cast<int>(basis.cols());
  if (constrained == 0) return Vector6d::Zero();
  const Matrix6d scaled = scale.asDiagonal() * hessian * scale.asDiagonal();
  Eigen::MatrixXd reduced = basis.transpose() * scaled * basis;
  reduced.diagonal().array() += damping * reduced.diagonal().maxCoeff();
  const Eigen::VectorXd rhs = -(basis.transpose() * (scale.asDiagonal() * gradient));
  const Eigen::VectorXd y = reduced.ldlt().solve(rhs);
  return scale.asDiagonal() * (basis * y);
}
inline Vector6d constrainedStep(const Matrix6d& hessian, const Vector6d& gradient, double length, double rcond,
                                double damping, int& constrained) {
  return constrainedStep(hessian, gradient, hessian, length, rcond, damping, constrained);
}

}  // namespace semfuse::tracking
