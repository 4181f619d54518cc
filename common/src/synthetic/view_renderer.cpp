#include "semfuse/synthetic/view_renderer.hpp"

#include <string>

#include <opencv2/core.hpp>

#include "semfuse/core/camera_check.hpp"

namespace semfuse::synthetic {

Ray pixelRay(const PinholeIntrinsics& k, const Pose& camera_to_world, double u, double v) {
  const Eigen::Vector3d camera_direction((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
  return Ray{camera_to_world.translation(), camera_to_world.linear() * camera_direction};
}

Result<RenderedView> renderView(const LabeledScene& scene, const PinholeIntrinsics& k, const Pose& camera_to_world) {
  if (Status camera = checkCamera(k, camera_to_world); !camera) return camera.errorInfo().prefixed("camera ");
  RenderedView view;
  view.intrinsics = k;
  view.camera_to_world = camera_to_world;
  view.depth = cv::Mat::zeros(k.height, k.width, CV_32FC1);
  view.color = cv::Mat::zeros(k.height, k.width, CV_8UC3);
  view.labels = cv::Mat::zeros(k.height, k.width, CV_16UC1);
  view.normals = cv::Mat::zeros(k.height, k.width, CV_32FC3);
  view.instances = cv::Mat::zeros(k.height, k.width, CV_16UC1);

  cv::parallel_for_(cv::Range(0, k.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      auto* depth = view.depth.ptr<float>(v);
      auto* color = view.color.ptr<cv::Vec3b>(v);
      auto* label = view.labels.ptr<uint16_t>(v);
      auto* normal = view.normals.ptr<cv::Vec3f>(v);
      auto* instance = view.instances.ptr<uint16_t>(v);
      for (int u = 0; u < k.width; ++u) {
        const auto hit = scene.castRay(pixelRay(k, camera_to_world, u, v));
        if (!hit) continue;
        depth[u] = static_cast<float>(hit->t);
        const Rgb rgb = scene.colorAt(*hit);
        color[u] = cv::Vec3b(rgb[0], rgb[1], rgb[2]);
        label[u] = scene.objects()[hit->object].label;
        instance[u] = static_cast<uint16_t>(scene.instanceOf(hit->object));
        normal[u] = cv::Vec3f(static_cast<float>(hit->normal.x()), static_cast<float>(hit->normal.y()),
                              static_cast<float>(hit->normal.z()));
      }
    }
  });
  return view;
}

}  // namespace semfuse::synthetic
