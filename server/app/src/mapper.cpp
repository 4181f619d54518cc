#include "mapper.hpp"

#include <chrono>
#include <cmath>
#include <utility>

namespace semfuse::server {
namespace {
double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

Mapper::Mapper(MapperOptions options, std::unique_ptr<PoseEstimator> estimator)
    : options_(std::move(options)), estimator_(std::move(estimator)), volume_(options_.volume) {}

Result<Pose> Mapper::choosePose(const Frame& frame, CameraTrack& track, FrameOutcome& outcome) {
  if (frame.camera_to_world && !(options_.refine_given_poses && estimator_ && track.has_pose)) {
    outcome.pose_state = PoseState::kGiven;
    return *frame.camera_to_world;
  }
  if (!track.has_pose) {
    if (frame.camera_to_world) {
      outcome.pose_state = PoseState::kGiven;
      return *frame.camera_to_world;
    }
    // The first frame of an empty map defines the world frame; any later camera must say where
    // it is, or its frames could never be placed consistently with the rest of the map.
    bool map_empty = false;
    {
      std::shared_lock lock(mutex_);
      map_empty = volume_.framesIntegrated() == 0;
    }
    if (!map_empty || !cameras_.empty())
      return makeError("camera '" + frame.camera_id +
                       "': first frame has no pose, and the map already has a world frame; "
                       "send the first frame of a new camera with its camera_to_world pose");
    outcome.pose_state = PoseState::kGiven;
    return Pose::Identity();
  }
  if (!estimator_) return makeError("frame without pose and the server has no tracker");

  const bool refining = frame.camera_to_world.has_value();
  const Pose guess = refining ? *frame.camera_to_world : Pose(track.velocity * track.last_pose);
  const auto start = std::chrono::steady_clock::now();
  PoseEstimator::Estimate estimate;
  {
    std::shared_lock lock(mutex_);
    estimate = estimator_->estimate(volume_, frame, guess);
  }
  outcome.track_ms = millisecondsSince(start);
  outcome.inlier_ratio = estimate.inlier_ratio;
  outcome.residual = estimate.residual;
  outcome.iterations = estimate.iterations;
  if (!estimate.ok) {
    outcome.pose_state = PoseState::kLost;
    outcome.lost_reason = estimate.failure;
    outcome.camera_to_world = guess;
    return guess;
  }
  outcome.pose_state = refining ? PoseState::kRefined : PoseState::kTracked;
  return estimate.camera_to_world;
}

Result<FrameOutcome> Mapper::integrateFrame(const Frame& frame, const Segmentation* segmentation) {
  FrameOutcome outcome;
  const bool known_camera = cameras_.count(frame.camera_id) > 0;
  CameraTrack candidate = known_camera ? cameras_.at(frame.camera_id) : CameraTrack{};
  auto pose = choosePose(frame, candidate, outcome);
  if (!pose.ok()) return Error{pose.error()};
  outcome.camera_to_world = pose.value();
  if (outcome.pose_state == PoseState::kLost) {
    // Keep the last good pose and velocity: the next frame starts from there.
    cameras_[frame.camera_id] = candidate;
    return outcome;
  }

  Frame posed = frame;  // shallow: cv::Mat shares pixels
  posed.camera_to_world = outcome.camera_to_world;
  const auto start = std::chrono::steady_clock::now();
  Result<volume::IntegrationStats> stats = volume::IntegrationStats{};
  {
    std::unique_lock lock(mutex_);
    stats = volume::integrate(volume_, posed, segmentation);
    if (stats.ok()) ++revision_;
  }
  outcome.integrate_ms = millisecondsSince(start);
  if (!stats.ok()) return Error{stats.error()};
  outcome.stats = stats.value();
  outcome.integrated = true;

  if (candidate.has_pose) candidate.velocity = outcome.camera_to_world * candidate.last_pose.inverse();
  candidate.last_pose = outcome.camera_to_world;
  candidate.has_pose = true;
  cameras_[frame.camera_id] = candidate;
  return outcome;
}

Result<volume::IntegrationStats> Mapper::integrateSegmentation(const HistoryEntry& frame,
                                                                const Segmentation& segmentation) {
  std::unique_lock lock(mutex_);
  auto stats = volume::integrateLabels(volume_, frame.depth, segmentation.labels, segmentation.confidence,
                                       frame.intrinsics, frame.camera_to_world);
  if (stats.ok()) ++revision_;
  return stats;
}

Status Mapper::save(const std::filesystem::path& path, const volume::MapExtraMetadata& extra) const {
  // Copy under the shared lock (fast, memory bound), write the copy without holding any lock.
  volume::LabeledVolume copy = read([](const volume::LabeledVolume& v) { return v.deepCopy(); });
  return volume::saveMap(copy, options_.legend, path, extra);
}

Status Mapper::load(const std::filesystem::path& path) {
  auto loaded = volume::loadMap(path);
  if (!loaded.ok()) return Error{loaded.error()};
  const auto& params = loaded.value().volume.params();
  const auto& mine = options_.volume;
  if (std::abs(params.voxel_size - mine.voxel_size) > 1e-9 || std::abs(params.truncation - mine.truncation) > 1e-9)
    return makeError(path.string() + ": map has voxel size " + std::to_string(params.voxel_size) +
                     " m and truncation " + std::to_string(params.truncation) +
                     " m; this server runs with " + std::to_string(mine.voxel_size) + " m / " +
                     std::to_string(mine.truncation) + " m (start it with the map's values)");
  std::unique_lock lock(mutex_);
  volume_ = std::move(loaded.value().volume);
  cameras_.clear();  // tracking restarts from the poses the next frames carry
  ++revision_;
  return Status::Ok();
}

void Mapper::reset() {
  std::unique_lock lock(mutex_);
  volume_.clear();
  cameras_.clear();
  ++revision_;
}

Mapper::Size Mapper::size() const {
  std::shared_lock lock(mutex_);
  return {volume_.allocatedVoxels(), volume_.allocatedLeaves(), volume_.observedVoxels(), volume_.memoryBytes(),
          volume_.framesIntegrated()};
}

uint64_t Mapper::revision() const {
  std::shared_lock lock(mutex_);
  return revision_;
}

}  // namespace semfuse::server
