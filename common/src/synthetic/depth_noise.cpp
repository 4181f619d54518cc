#include "semfuse/synthetic/depth_noise.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "hash_noise.hpp"

namespace semfuse::synthetic {
namespace {

double degToRad(double deg) { return deg * M_PI / 180.0; }

// Independent random streams per pixel: which stream a draw uses must not depend on other draws.
enum Stream : uint64_t { kGaussA = 1, kGaussB = 2, kGrazing = 3, kDropout = 4 };

}  // namespace

double axialSigma(const DepthNoiseParams& p, double z, double theta) {
  const double dz = z - p.z_reference;
  double sigma = p.sigma_base + p.sigma_quadratic * dz * dz;
  // The angular term diverges at 90 degrees; pixels that close to grazing are dropped anyway.
  const double theta_capped = std::min(theta, degToRad(89.0));
  const double tan_like = theta_capped / (0.5 * M_PI - theta_capped);
  sigma += p.sigma_angular * tan_like * tan_like / std::sqrt(std::max(z, 1e-3));
  return sigma;
}

cv::Mat applyDepthNoise(const RenderedView& view, const DepthNoiseParams& p, uint64_t seed, uint64_t frame_index) {
  cv::Mat noisy = cv::Mat::zeros(view.depth.size(), CV_32FC1);
  const PinholeIntrinsics& k = view.intrinsics;
  const Eigen::Matrix3d world_to_camera = view.camera_to_world.linear().transpose();
  const uint64_t frame_key = hashCombine(seed, frame_index);
  const double grazing_start = degToRad(p.grazing_start_deg);
  const double grazing_max = degToRad(std::max(p.grazing_max_deg, p.grazing_start_deg));

  cv::parallel_for_(cv::Range(0, view.depth.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const auto* depth = view.depth.ptr<float>(v);
      const auto* normal = view.normals.ptr<cv::Vec3f>(v);
      auto* out = noisy.ptr<float>(v);
      for (int u = 0; u < view.depth.cols; ++u) {
        const double z = depth[u];
        if (!(z > 0.0)) continue;
        const uint64_t pixel_key = hashCombine(frame_key, static_cast<uint64_t>(v) * k.width + u);
        auto draw = [&](Stream s) { return hashCombine(pixel_key, s); };

        // Incidence angle between the viewing ray and the surface normal, in the camera frame.
        const Eigen::Vector3d ray = Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0).normalized();
        const Eigen::Vector3d n = world_to_camera * Eigen::Vector3d(normal[u][0], normal[u][1], normal[u][2]);
        const double theta = std::acos(std::clamp(-ray.dot(n), 0.0, 1.0));
        if (theta >= grazing_max) continue;
        if (theta > grazing_start &&
            unitFromHash(draw(kGrazing)) < (theta - grazing_start) / (grazing_max - grazing_start))
          continue;
        if (unitFromHash(draw(kDropout)) < p.dropout_probability) continue;

        double noisy_z = z + axialSigma(p, z, theta) * gaussianFromHashes(draw(kGaussA), draw(kGaussB));
        if (p.disparity_step > 0.0 && p.focal_baseline > 0.0 && noisy_z > 0.0) {
          const double disparity = p.focal_baseline / noisy_z;
          const double quantised = std::round(disparity / p.disparity_step) * p.disparity_step;
          noisy_z = quantised > 0.0 ? p.focal_baseline / quantised : 0.0;
        }
        if (noisy_z < p.min_range || noisy_z > p.max_range) continue;
        out[u] = static_cast<float>(noisy_z);
      }
    }
  });
  return noisy;
}

}  // namespace semfuse::synthetic
