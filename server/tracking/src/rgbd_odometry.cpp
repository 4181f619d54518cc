#include "semfuse/tracking/rgbd_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <opencv2/core.hpp>

#include "semfuse/tracking/normal_equations.hpp"
#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {
namespace {

// What the current image offers at each pixel: intensity and depth with their image gradients
// (central differences; a depth gradient across a depth edge is marked invalid with NaN).
struct CurrentLevel {
  cv::Mat intensity, intensity_dx, intensity_dy;
  cv::Mat depth, depth_dx, depth_dy;
  PinholeIntrinsics k;
};

constexpr float kDepthEdge = 0.1f;  // metres: neighbours farther apart are on different surfaces

CurrentLevel prepareCurrent(const ImageLevel& level) {
  CurrentLevel out;
  out.k = level.intrinsics;
  out.depth = level.depth;
  const int rows = level.depth.rows, cols = level.depth.cols;
  out.depth_dx.create(rows, cols, CV_32FC1);
  out.depth_dy.create(rows, cols, CV_32FC1);
  const float nan = std::nanf("");
  for (int v = 0; v < rows; ++v) {
    for (int u = 0; u < cols; ++u) {
      auto z = [&](int uu, int vv) { return level.depth.at<float>(vv, uu); };
      float dx = nan, dy = nan;
      if (u > 0 && u + 1 < cols) {
        const float a = z(u - 1, v), b = z(u + 1, v);
        if (a > 0.0f && b > 0.0f && std::abs(a - b) < kDepthEdge) dx = 0.5f * (b - a);
      }
      if (v > 0 && v + 1 < rows) {
        const float a = z(u, v - 1), b = z(u, v + 1);
        if (a > 0.0f && b > 0.0f && std::abs(a - b) < kDepthEdge) dy = 0.5f * (b - a);
      }
      out.depth_dx.at<float>(v, u) = dx;
      out.depth_dy.at<float>(v, u) = dy;
    }
  }
  if (!level.intensity.empty()) {
    out.intensity = level.intensity;
    out.intensity_dx = cv::Mat::zeros(rows, cols, CV_32FC1);
    out.intensity_dy = cv::Mat::zeros(rows, cols, CV_32FC1);
    for (int v = 1; v + 1 < rows; ++v)
      for (int u = 1; u + 1 < cols; ++u) {
        out.intensity_dx.at<float>(v, u) =
            0.5f * (level.intensity.at<float>(v, u + 1) - level.intensity.at<float>(v, u - 1));
        out.intensity_dy.at<float>(v, u) =
            0.5f * (level.intensity.at<float>(v + 1, u) - level.intensity.at<float>(v - 1, u));
      }
  }
  return out;
}

// Bilinear value of a float image at (u, v) inside [0, cols-1) x [0, rows-1).
float bilinear(const cv::Mat& image, float u, float v) {
  const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
  const float fu = u - static_cast<float>(u0), fv = v - static_cast<float>(v0);
  const float* r0 = image.ptr<float>(v0) + u0;
  const float* r1 = image.ptr<float>(v0 + 1) + u0;
  return (1 - fv) * ((1 - fu) * r0[0] + fu * r0[1]) + fv * ((1 - fu) * r1[0] + fu * r1[1]);
}

// Bilinear depth where all four neighbours are valid and on one surface; else 0.
float bilinearDepth(const cv::Mat& depth, float u, float v) {
  const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
  const float* r0 = depth.ptr<float>(v0) + u0;
  const float* r1 = depth.ptr<float>(v0 + 1) + u0;
  const float a = r0[0], b = r0[1], c = r1[0], d = r1[1];
  if (!(a > 0.0f && b > 0.0f && c > 0.0f && d > 0.0f)) return 0.0f;
  if (std::max(std::max(a, b), std::max(c, d)) - std::min(std::min(a, b), std::min(c, d)) > kDepthEdge) return 0.0f;
  const float fu = u - static_cast<float>(u0), fv = v - static_cast<float>(v0);
  return (1 - fv) * ((1 - fu) * a + fu * b) + fv * ((1 - fu) * c + fu * d);
}

struct ReferencePoint {
  Eigen::Vector3f point;
  float intensity;  // NaN without intensity
};

// The pixels with depth, on a grid of stride s (in both directions) such that about max_points remain.
std::vector<ReferencePoint> referencePoints(const ImageLevel& level, std::size_t max_points) {
  std::vector<ReferencePoint> points;
  const PinholeIntrinsics& k = level.intrinsics;
  const bool with_intensity = !level.intensity.empty();
  int stride = 1;
  if (max_points > 0) {
    const auto valid = static_cast<double>(cv::countNonZero(level.depth > 0.0f));
    stride = std::max(1, static_cast<int>(std::lround(std::sqrt(valid / static_cast<double>(max_points)))));
  }
  for (int v = 0; v < level.depth.rows; v += stride)
    for (int u = 0; u < level.depth.cols; u += stride) {
      const float z = level.depth.at<float>(v, u);
      if (!(z > 0.0f)) continue;
      points.push_back(
          {Eigen::Vector3f(static_cast<float>((u - k.cx) / k.fx) * z, static_cast<float>((v - k.cy) / k.fy) * z, z),
           with_intensity ? level.intensity.at<float>(v, u) : std::nanf("")});
    }
  return points;
}

struct PassResult {
  NormalEquations system;
  std::size_t landed = 0;
  std::size_t matched = 0;
  double intensity_sq = 0.0;
  std::size_t intensity_count = 0;
  void join(const PassResult& other) {
    system.join(other.system);
    landed += other.landed;
    matched += other.matched;
    intensity_sq += other.intensity_sq;
    intensity_count += other.intensity_count;
  }
};

PassResult accumulate(const std::vector<ReferencePoint>& points, const CurrentLevel& current, const Pose& pose,
                      const OdometryParams& params, bool photometric) {
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  const Eigen::Vector3f translation = pose.translation().cast<float>();
  const auto fx = static_cast<float>(current.k.fx), fy = static_cast<float>(current.k.fy);
  const auto cx = static_cast<float>(current.k.cx), cy = static_cast<float>(current.k.cy);
  const float max_u = static_cast<float>(current.depth.cols - 1) - 1e-3f;
  const float max_v = static_cast<float>(current.depth.rows - 1) - 1e-3f;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size(), 256), PassResult{},
      [&](const tbb::blocked_range<std::size_t>& range, PassResult pass) {
        Eigen::Matrix<float, 6, 1> jacobian;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const Eigen::Vector3f q = rotation * points[i].point + translation;
          if (!(q.z() > 0.05f)) continue;
          const float inv_z = 1.0f / q.z();
          const float u = fx * q.x() * inv_z + cx, v = fy * q.y() * inv_z + cy;
          if (!(u >= 0.0f && v >= 0.0f && u < max_u && v < max_v)) continue;
          ++pass.system.observed;
          // d(u, v)/dq of the projection.
          const float du_dx = fx * inv_z, du_dz = -fx * q.x() * inv_z * inv_z;
          const float dv_dy = fy * inv_z, dv_dz = -fy * q.y() * inv_z * inv_z;
          auto chain = [&](float gu, float gv) {  // image gradient -> gradient w.r.t. q
            return Eigen::Vector3f(gu * du_dx, gv * dv_dy, gu * du_dz + gv * dv_dz);
          };
          const float z = bilinearDepth(current.depth, u, v);
          const float rz = z - q.z();
          if (z > 0.0f) {
            ++pass.landed;
            if (std::abs(rz) < 2.0f * params.depth_scale_m + 0.01f * q.z()) ++pass.matched;
          }
          if (z > 0.0f && std::abs(rz) > params.max_depth_difference_m) continue;  // occluded either way
          if (z > 0.0f) {
            const float gu = bilinear(current.depth_dx, u, v), gv = bilinear(current.depth_dy, u, v);
            if (std::isfinite(gu) && std::isfinite(gv)) {
              const Eigen::Vector3f g = chain(gu, gv) - Eigen::Vector3f::UnitZ();
              jacobian.head<3>() = g;
              jacobian.tail<3>() = q.cross(g);
              const float a = std::abs(rz);
              const float huber = a <= params.depth_scale_m ? 1.0f : params.depth_scale_m / a;
              pass.system.add(jacobian, rz, params.depth_weight * huber);
            }
          }
          if (!photometric || std::isnan(points[i].intensity)) continue;
          const float ri = bilinear(current.intensity, u, v) - points[i].intensity;
          const Eigen::Vector3f g = chain(bilinear(current.intensity_dx, u, v), bilinear(current.intensity_dy, u, v));
          jacobian.head<3>() = g;
          jacobian.tail<3>() = q.cross(g);
          const float a = std::abs(ri);
          pass.system.add(jacobian, ri, a <= params.intensity_scale ? 1.0f : params.intensity_scale / a);
          pass.intensity_sq += static_cast<double>(ri) * ri;
          ++pass.intensity_count;
        }
        return pass;
      },
      [](PassResult a, const PassResult& b) {
        a.join(b);
        return a;
      });
}

}  // namespace

OdometryResult alignImages(const ImagePyramid& reference, const ImagePyramid& current, const Pose& initial,
                           const OdometryParams& params) {
  OdometryResult result;
  result.current_from_reference = initial;
  if (reference.empty() || current.empty()) return result;
  const bool photometric = reference.hasIntensity() && current.hasIntensity();
  Pose pose = initial;
  PassResult last;
  std::vector<ReferencePoint> points;
  const int finest = std::max(reference.finestLevel(), current.finestLevel());
  for (int level = ImagePyramid::kLevels - 1; level >= finest; --level) {
    points = referencePoints(reference.level(level), params.max_points[static_cast<std::size_t>(level)]);
    const CurrentLevel target = prepareCurrent(current.level(level));
    double length = 0.0;
    for (const auto& p : points) length += p.point.z();
    length = points.empty() ? 1.0 : std::max(0.1, length / static_cast<double>(points.size()));
    for (int it = 0; it < params.max_iterations[static_cast<std::size_t>(level)]; ++it) {
      last = accumulate(points, target, pose, params, photometric);
      if (last.system.residuals < 12) break;
      int constrained = 0;
      const Vector6d step =
          constrainedStep(last.system.hessian(), last.system.gradient(), length, 1e-4, 1e-4, constrained);
      if (!step.allFinite()) break;
      pose = expSE3(step) * pose;
      if (step.norm() < params.convergence_norm) break;
    }
    if (level == finest) last = accumulate(points, target, pose, params, photometric);
  }
  result.current_from_reference = orthonormalized(pose);
  result.points = points.size();
  result.landed = last.landed;
  result.matched = last.matched;
  result.overlap = points.empty() ? 0.0 : static_cast<double>(last.landed) / static_cast<double>(points.size());
  result.matched_ratio = last.landed == 0 ? 0.0 : static_cast<double>(last.matched) / static_cast<double>(last.landed);
  result.intensity_rms =
      last.intensity_count > 0 ? std::sqrt(last.intensity_sq / static_cast<double>(last.intensity_count)) : 0.0;
  return result;
}

}  // namespace semfuse::tracking
