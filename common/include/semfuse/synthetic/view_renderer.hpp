#pragma once
// Exact images of a LabeledScene seen by a pinhole camera: what an ideal RGB-D sensor and a
// perfect segmenter would return.
#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/synthetic/labeled_scene.hpp"

namespace semfuse::synthetic {

struct RenderedView {
  PinholeIntrinsics intrinsics;
  Pose camera_to_world = Pose::Identity();
  cv::Mat depth;      // CV_32FC1, metres along the camera z axis; 0 where the ray hits nothing
  cv::Mat color;      // CV_8UC3, RGB; black where nothing is hit
  cv::Mat labels;     // CV_16UC1, 0 where nothing is hit
  cv::Mat normals;    // CV_32FC3, unit outward surface normal in WORLD coordinates; 0 where no hit
  cv::Mat instances;  // CV_16UC1, the object instance hit (SceneObject::instance), 0 where no hit
};

// The world-frame ray through the centre of pixel (u, v), scaled so that t = camera depth.
Ray pixelRay(const PinholeIntrinsics& intrinsics, const Pose& camera_to_world, double u, double v);

// Renders all layers, in parallel over rows. Fails on a camera that semfuse/core/camera_check.hpp
// refuses (the message starts with "camera ").
Result<RenderedView> renderView(const LabeledScene& scene, const PinholeIntrinsics& intrinsics,
                                const Pose& camera_to_world);

}  // namespace semfuse::synthetic
