#pragma once
// Gauss-Newton normal equations of a 6-DoF alignment, accumulated point by point: the upper
// triangle of J^T W J (21 values) and J^T W r (6 values) in double precision, so that summing
// tens of thousands of float Jacobians in any order (parallel reduction) loses no digits.
#include <array>
#include <cstddef>

#include <Eigen/Core>

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

}  // namespace semfuse::tracking
