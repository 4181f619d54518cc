#include "objects/objects_picture.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/objects/object_mesh.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/tracking/se3.hpp"

namespace semfuse::bench {
namespace {

constexpr int kMinPixelsForName = 100;

// Neighbouring ids get far-apart hues (golden-ratio steps around the colour wheel).
cv::Vec3f idColor(int32_t id) {
  const float hue = static_cast<float>(std::fmod(static_cast<double>(id) * 0.618033988749895, 1.0)) * 360.0f;
  cv::Mat3f hsv(1, 1, cv::Vec3f(hue, 0.7f, 1.0f)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr(0, 0);
}

}  // namespace

Result<ObjectsPicture> writeObjectsPicture(const volume::LabeledVolume& map, const objects::ObjectSet& objects,
                                           const LabelLegend& legend, const Pose& camera_to_world,
                                           const PinholeIntrinsics& k, const std::string& png_path) {
  render::RaycastOptions options;
  options.layers = kDepthLayer | kNormalsLayer;
  options.max_depth = 12.0;
  auto cast = render::raycast(map, k, camera_to_world, options);
  if (!cast) return makeError("raycast: " + cast.error());
  const cv::Mat& depth = cast.value().depth;
  const cv::Mat& normals = cast.value().normals;
  if (!objects.ids) return makeError("the object set has no id tree");

  cv::Mat3b image(k.height, k.width, cv::Vec3b(255, 255, 255));
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> ids(*objects.ids);
  const auto voxel = static_cast<float>(map.voxelSize());
  std::map<int32_t, std::vector<cv::Point>> pixels_of;
  std::size_t surface_pixels = 0, object_pixels = 0;
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const float z = depth.at<float>(v, u);
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      ++surface_pixels;
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d world = camera_to_world * (ray * z);
      const int32_t id = objects::objectIdNear(ids, world.cast<float>(), voxel);
      // Shaded by how squarely the surface faces the camera, so that shapes read.
      const cv::Vec3f n = normals.at<cv::Vec3f>(v, u);
      const Eigen::Vector3d view = camera_to_world.linear() * ray.normalized();
      const double facing = std::abs(view.dot(Eigen::Vector3d(n[0], n[1], n[2])));
      const float shade = static_cast<float>(0.35 + 0.65 * (std::isfinite(facing) ? facing : 0.0));
      const cv::Vec3f base = id > 0 ? idColor(id) : cv::Vec3f(0.75f, 0.75f, 0.75f);
      image(v, u) = cv::Vec3b(cv::saturate_cast<uchar>(255.0f * base[0] * shade),
                              cv::saturate_cast<uchar>(255.0f * base[1] * shade),
                              cv::saturate_cast<uchar>(255.0f * base[2] * shade));
      if (id > 0) {
        ++object_pixels;
        pixels_of[id].emplace_back(u, v);
      }
    }
  }

  ObjectsPicture out;
  out.covered = surface_pixels == 0 ? 0.0 : static_cast<double>(object_pixels) / static_cast<double>(surface_pixels);
  // Each object's name at the median of its pixels, where most of it is seen.
  for (auto& [id, points] : pixels_of) {
    const objects::TrackedObject* object = objects.find(static_cast<uint32_t>(id));
    if (!object || object->fragment || static_cast<int>(points.size()) < kMinPixelsForName) continue;
    ++out.objects_in_view;
    auto middle = points.begin() + static_cast<std::ptrdiff_t>(points.size() / 2);
    std::nth_element(points.begin(), middle, points.end(),
                     [](const cv::Point& a, const cv::Point& b) { return a.x < b.x; });
    const int x = middle->x;
    std::nth_element(points.begin(), middle, points.end(),
                     [](const cv::Point& a, const cv::Point& b) { return a.y < b.y; });
    const int y = middle->y;
    const LabelInfo* info = legend.find(object->label);
    const std::string text = (info ? info->name : "label " + std::to_string(object->label)) + " " + std::to_string(id);
    const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, nullptr);
    const cv::Point at(std::clamp(x - size.width / 2, 2, std::max(2, k.width - size.width - 2)),
                       std::clamp(y + size.height / 2, size.height + 2, k.height - 2));
    cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
    cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  }
  if (!cv::imwrite(png_path, image)) return makeError("cannot write " + png_path);
  return out;
}

Result<Pose> readPoseMatrix(const std::string& path) {
  std::ifstream in(path);
  if (!in) return makeError("cannot read " + path);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (!(in >> m(r, c))) return makeError(path + ": expected 16 numbers (a 4x4 camera-to-world matrix)");
  if (!m.allFinite()) return makeError(path + ": the matrix is not finite");
  Pose pose = Pose::Identity();
  pose.matrix() = m;
  return tracking::orthonormalized(pose);
}

}  // namespace semfuse::bench
