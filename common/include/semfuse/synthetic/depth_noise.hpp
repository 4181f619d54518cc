#pragma once
// Kinect-like corruption of an exact depth image (structured-light sensor model):
//  - axial Gaussian noise whose standard deviation grows with depth squared and with the angle
//    between the ray and the surface (Nguyen et al., 3DIMPVT 2012 give the shape of both terms),
//  - quantisation in disparity, so depth steps grow with z^2 as on a real sensor,
//  - dropouts: at grazing incidence (the projected pattern is lost), randomly, and out of range.
// Deterministic: the same view, parameters and seed give the same image, bit for bit.
#include <cstdint>

#include <opencv2/core/mat.hpp>

#include "semfuse/synthetic/view_renderer.hpp"

namespace semfuse::synthetic {

struct DepthNoiseParams {
  // sigma(z, theta) = sigma_base + sigma_quadratic * (z - z_reference)^2
  //                   + sigma_angular * theta^2 / (pi/2 - theta)^2 / sqrt(z)      [metres]
  double sigma_base = 0.0012;
  double sigma_quadratic = 0.0019;
  double z_reference = 0.4;
  double sigma_angular = 0.0001;
  // Disparity quantisation: d = focal_baseline / z pixels, rounded to disparity_step pixels.
  // 0 disables it. Kinect v1: focal 580 px x baseline 0.075 m, 1/8 px steps.
  double focal_baseline = 580.0 * 0.075;
  double disparity_step = 1.0 / 8.0;
  // Incidence angle (ray vs surface normal) beyond which the pixel is always lost, and the
  // angle from which the dropout probability ramps linearly up to 1 there.
  double grazing_start_deg = 70.0;
  double grazing_max_deg = 85.0;
  double dropout_probability = 0.002;  // independent of geometry
  double min_range = 0.3;
  double max_range = 6.0;
};

// Noisy copy of view.depth (CV_32FC1); invalid pixels are 0. frame_index decorrelates frames
// rendered with the same seed.
cv::Mat applyDepthNoise(const RenderedView& view, const DepthNoiseParams& params, uint64_t seed,
                        uint64_t frame_index = 0);

// Standard deviation of the axial noise the model uses at depth z and incidence angle theta.
double axialSigma(const DepthNoiseParams& params, double z, double theta_rad);

}  // namespace semfuse::synthetic
