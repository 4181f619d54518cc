#include "semfuse/tracking/keypoint_map.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/tracking/hamming_match.hpp"
#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {
namespace {

// A keypoint's depth is trusted when its 3x3 neighbourhood lies on one surface: at a depth edge
// (and where colour and depth are registered only roughly) the pixel may read the other side.
constexpr float kSurfaceSpread = 0.03f;  // relative depth spread allowed within the neighbourhood

bool depthOnSurface(const cv::Mat& depth, int u, int v, float& z) {
  if (u < 1 || v < 1 || u + 1 >= depth.cols || v + 1 >= depth.rows) return false;
  z = depth.at<float>(v, u);
  if (!(z > 0.0f) || !std::isfinite(z)) return false;
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const float n = depth.at<float>(v + dv, u + du);
      if (!(n > 0.0f) || std::abs(n - z) > kSurfaceSpread * z) return false;
    }
  }
  return true;
}

// Two stored keypoints this close are one point of the scene seen by two keyframes.
constexpr float kSamePoint = 0.03f;

cv::Matx33d cameraMatrix(const PinholeIntrinsics& k) { return {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0}; }

}  // namespace

KeypointMap::KeypointMap(KeypointParams params) : params_(params) {}

FrameKeypoints KeypointMap::detect(const cv::Mat& color, const cv::Mat& depth,
                                   const PinholeIntrinsics& intrinsics) const {
  FrameKeypoints out;
  if (color.empty() || depth.empty() || color.type() != CV_8UC3 || depth.type() != CV_32FC1) return out;
  cv::Mat gray;
  cv::cvtColor(color, gray, cv::COLOR_RGB2GRAY);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  // A detector per call: OpenCV does not promise that one may serve several threads at once, and
  // making one costs nothing beside the detection.
  cv::ORB::create(std::max(1, params_.features))->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  // Colour and depth may differ in size: a keypoint reads the depth at the same place in the image.
  const double to_depth_u = static_cast<double>(depth.cols) / color.cols;
  const double to_depth_v = static_cast<double>(depth.rows) / color.rows;
  const double to_intrinsics = static_cast<double>(intrinsics.width) / depth.cols;
  std::vector<int> kept;
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point2f& p = keypoints[i].pt;
    const double du = p.x * to_depth_u, dv = p.y * to_depth_v;
    float z = 0.0f;
    if (!depthOnSurface(depth, static_cast<int>(std::lround(du)), static_cast<int>(std::lround(dv)), z)) continue;
    const double u = du * to_intrinsics, v = dv * to_intrinsics;
    out.pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
    out.points.emplace_back(static_cast<float>((u - intrinsics.cx) / intrinsics.fx * z),
                            static_cast<float>((v - intrinsics.cy) / intrinsics.fy * z), z);
    kept.push_back(static_cast<int>(i));
  }
  out.descriptors.create(static_cast<int>(kept.size()), descriptors.cols, CV_8UC1);
  for (std::size_t i = 0; i < kept.size(); ++i)
    descriptors.row(kept[i]).copyTo(out.descriptors.row(static_cast<int>(i)));
  return out;
}

void KeypointMap::add(const FrameKeypoints& keypoints, const Pose& camera_to_world) {
  StoredKeyframe stored;
  // Keypoints not as detect() makes them (a descriptor per point, 32 bytes each) are not kept.
  if (keypoints.descriptors.rows != static_cast<int>(keypoints.size()) ||
      (!keypoints.empty() && (keypoints.descriptors.cols != 32 || keypoints.descriptors.type() != CV_8UC1))) {
    keyframes_.push_back(std::move(stored));
    return;
  }
  stored.first_row = all_descriptors_.rows;
  stored.world_points.reserve(keypoints.size());
  for (const Eigen::Vector3f& p : keypoints.points) {
    const Eigen::Vector3d w = camera_to_world * p.cast<double>();
    stored.world_points.emplace_back(static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(w.z()));
  }
  if (!keypoints.descriptors.empty()) {
    all_descriptors_.push_back(keypoints.descriptors);
    owner_.insert(owner_.end(), static_cast<std::size_t>(keypoints.descriptors.rows),
                  static_cast<uint32_t>(keyframes_.size()));
  }
  keyframes_.push_back(std::move(stored));
}

void KeypointMap::clear() {
  keyframes_.clear();
  all_descriptors_.release();
  owner_.clear();
  next_row_ = 0;
}

std::vector<int> KeypointMap::vote(const FrameKeypoints& frame) {
  std::vector<int> votes(keyframes_.size(), 0);
  const std::size_t rows = owner_.size();
  if (rows == 0) return votes;
  // The whole store when it is small; otherwise the next max_compared rows, so that a camera that
  // stays lost has compared itself with every keyframe after a few frames.
  std::size_t begin = 0, end = rows;
  if (rows > params_.max_compared) {
    if (next_row_ >= rows) next_row_ = 0;
    begin = next_row_;
    end = std::min(rows, begin + params_.max_compared);
    next_row_ = end;
  }
  const cv::Mat window = all_descriptors_.rowRange(static_cast<int>(begin), static_cast<int>(end));
  for (const NearestTwo& nearest : nearestTwo(frame.descriptors, window))
    if (nearest.best >= 0 && nearest.best_distance <= params_.max_hamming)
      ++votes[owner_[begin + static_cast<std::size_t>(nearest.best)]];
  return votes;
}

bool KeypointMap::solve(const FrameKeypoints& frame, const PinholeIntrinsics& intrinsics,
                        const std::vector<std::size_t>& keyframes, KeypointPose& out) {
  // The chosen keyframes' points together: a place seen by several keyframes gives each of its
  // points several times, at nearly one world position.
  cv::Mat descriptors;
  std::vector<cv::Point3f> points;
  for (std::size_t k : keyframes) {
    const StoredKeyframe& stored = keyframes_[k];
    if (stored.world_points.empty()) continue;
    descriptors.push_back(
        all_descriptors_.rowRange(stored.first_row, stored.first_row + static_cast<int>(stored.world_points.size())));
    points.insert(points.end(), stored.world_points.begin(), stored.world_points.end());
  }
  const std::vector<NearestTwo> nearest = nearestTwo(frame.descriptors, descriptors);
  std::vector<cv::Point3f> world;
  std::vector<cv::Point2f> pixels;
  for (std::size_t q = 0; q < nearest.size(); ++q) {
    const NearestTwo& n = nearest[q];
    if (n.best < 0 || n.best_distance > params_.max_hamming) continue;
    const cv::Point3f& point = points[static_cast<std::size_t>(n.best)];
    if (n.second >= 0 && n.best_distance > params_.ratio * static_cast<float>(n.second_distance)) {
      // Ambiguous, unless both candidates are the same point seen by two keyframes.
      const cv::Point3f d = point - points[static_cast<std::size_t>(n.second)];
      if (d.dot(d) > kSamePoint * kSamePoint) continue;
    }
    world.push_back(point);
    pixels.push_back(frame.pixels[q]);
  }
  out.keyframe = keyframes.front();
  last_ = {world, pixels};
  out.matches = static_cast<int>(world.size());
  if (out.matches < std::max(params_.min_matches, 4)) return false;
  const cv::Matx33d k = cameraMatrix(intrinsics);
  const double threshold = params_.reprojection_px * intrinsics.width / 640.0;
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(world, pixels, k, cv::noArray(), rvec, tvec, false, params_.ransac_iterations,
                          static_cast<float>(threshold), 0.999, inliers, cv::SOLVEPNP_AP3P))
    return false;
  out.inliers = static_cast<int>(inliers.size());
  if (out.inliers < params_.min_inliers) return false;
  // Refined on the inliers alone (RANSAC's answer comes from its best minimal sample).
  std::vector<cv::Point3f> inlier_world;
  std::vector<cv::Point2f> inlier_pixels;
  for (int i : inliers) {
    inlier_world.push_back(world[static_cast<std::size_t>(i)]);
    inlier_pixels.push_back(pixels[static_cast<std::size_t>(i)]);
  }
  cv::solvePnPRefineLM(inlier_world, inlier_pixels, k, cv::noArray(), rvec, tvec);
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Pose world_to_camera = Pose::Identity();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) world_to_camera.linear()(row, col) = r(row, col);
    world_to_camera.translation()(row) = tvec.at<double>(row);
  }
  if (!world_to_camera.matrix().allFinite()) return false;
  out.camera_to_world = orthonormalized(world_to_camera.inverse());
  return true;
}

int KeypointMatches::explainedBy(const Pose& camera_to_world, const PinholeIntrinsics& intrinsics,
                                 double max_px) const {
  const Eigen::Isometry3d world_to_camera = camera_to_world.inverse();
  int count = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    const Eigen::Vector3d p = world_to_camera * Eigen::Vector3d(world[i].x, world[i].y, world[i].z);
    if (p.z() <= 0.0) continue;
    const double u = intrinsics.fx * p.x() / p.z() + intrinsics.cx, v = intrinsics.fy * p.y() / p.z() + intrinsics.cy;
    if (std::hypot(u - pixels[i].x, v - pixels[i].y) <= max_px) ++count;
  }
  return count;
}

std::optional<KeypointPose> KeypointMap::locate(const FrameKeypoints& frame, const PinholeIntrinsics& intrinsics) {
  last_ = {};
  if (frame.size() < static_cast<std::size_t>(params_.min_matches) || keyframes_.empty()) return std::nullopt;
  const std::vector<int> votes = vote(frame);
  std::vector<std::size_t> order(votes.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const std::size_t tried = std::min(params_.keyframes_tried, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(tried), order.end(),
                    [&](std::size_t a, std::size_t b) { return votes[a] > votes[b]; });
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < tried && votes[order[i]] >= params_.min_matches / 2; ++i) chosen.push_back(order[i]);
  if (chosen.empty()) return std::nullopt;
  KeypointPose pose;
  if (!solve(frame, intrinsics, chosen, pose)) return std::nullopt;
  return pose;
}

}  // namespace semfuse::tracking
