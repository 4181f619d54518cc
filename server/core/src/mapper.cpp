#include "mapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "semfuse/tracking/volume_field.hpp"
#include "semfuse/volume/free_space.hpp"

namespace semfuse::server {
namespace {
double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

namespace {
tracking::TrackerConfig trackerConfig(const MapperOptions& options) {
  tracking::TrackerConfig config;
  config.alignment = options.tracker;
  config.given_pose =
      options.refine_given_poses ? tracking::GivenPosePolicy::kRefine : tracking::GivenPosePolicy::kUseAsIs;
  return config;
}
}  // namespace

Mapper::Mapper(MapperOptions options)
    : options_(std::move(options)), tracker_(trackerConfig(options_)), volume_(options_.volume) {}

namespace {
PoseState poseStateOf(tracking::TrackingStatus status) {
  switch (status) {
    case tracking::TrackingStatus::kInitialized:
    case tracking::TrackingStatus::kGivenPose:
      return PoseState::kGiven;
    case tracking::TrackingStatus::kRefined:
      return PoseState::kRefined;
    case tracking::TrackingStatus::kTracked:
    case tracking::TrackingStatus::kRelocalised:
      return PoseState::kTracked;
    case tracking::TrackingStatus::kLost:
      break;
  }
  return PoseState::kLost;
}
}  // namespace

Result<tracking::TrackedFrame> Mapper::choosePose(const Frame& frame, FrameOutcome& outcome) {
  const auto start = std::chrono::steady_clock::now();
  Result<tracking::TrackedFrame> tracked = tracking::TrackedFrame{};
  {
    std::shared_lock lock(mutex_);
    tracking::VolumeField field(volume_);
    tracked = tracker_.track(frame, field, volume_.framesIntegrated() == 0);
  }
  outcome.track_ms = millisecondsSince(start);
  if (!tracked.ok()) return tracked;

  const tracking::TrackedFrame& t = tracked.value();
  outcome.pose_state = poseStateOf(t.status);
  outcome.camera_to_world = t.pose;
  outcome.inlier_ratio = static_cast<float>(t.quality.inlier_ratio);
  outcome.residual = static_cast<float>(t.quality.rms_residual_m);
  outcome.iterations = static_cast<uint32_t>(t.quality.iterations);
  if (!t.shouldIntegrate()) outcome.lost_reason = tracking::toString(t.lost_reason);
  const tracking::CameraTrackingSummary summary = tracker_.camera(frame.camera_id);
  outcome.frames_since_lost = summary.frames_since_lost;
  outcome.relocalisations = summary.relocalisations;
  return tracked;
}

Result<FrameOutcome> Mapper::integrateFrame(const Frame& frame, const Segmentation* segmentation) {
  FrameOutcome outcome;
  auto tracked = choosePose(frame, outcome);
  if (!tracked.ok()) return tracked.errorInfo();
  if (!tracked.value().shouldIntegrate()) return outcome;

  Frame posed = frame;  // shallow: cv::Mat shares pixels
  posed.camera_to_world = outcome.camera_to_world;
  const auto start = std::chrono::steady_clock::now();
  Result<volume::IntegrationStats> stats = volume::IntegrationStats{};
  {
    std::unique_lock lock(mutex_);
    stats = volume::integrate(volume_, posed, segmentation);
    if (stats.ok()) ++revision_;
    // The frame passed the same checks in integrate(): this cannot fail on its input.
    if (stats.ok() && options_.observe_free_space)
      static_cast<void>(volume::observeFreeSpace(volume_, posed.depth, posed.intrinsics, *posed.camera_to_world,
                                                 options_.free_space_stride));
  }
  outcome.integrate_ms = millisecondsSince(start);
  if (!stats.ok()) return stats.errorInfo();
  if (on_change_) on_change_();
  outcome.stats = stats.value();
  outcome.integrated = true;
  tracker_.integrated(frame, tracked.value());
  return outcome;
}

Result<volume::IntegrationStats> Mapper::integrateSegmentation(const HistoryEntry& frame,
                                                               const Segmentation& segmentation) {
  std::unique_lock lock(mutex_);
  auto stats = volume::integrateLabels(volume_, frame.depth, segmentation.labels, segmentation.confidence,
                                       frame.intrinsics, frame.camera_to_world);
  if (stats.ok()) ++revision_;
  lock.unlock();
  if (stats.ok() && on_change_) on_change_();
  return stats;
}

Status Mapper::save(const std::filesystem::path& path, const volume::MapExtraMetadata& extra) const {
  // Copy under the shared lock (fast, memory bound), write the copy without holding any lock.
  volume::LabeledVolume copy = read([](const volume::LabeledVolume& v) { return v.deepCopy(); });
  return volume::saveMap(copy, options_.legend, path, extra);
}

Status Mapper::load(const std::filesystem::path& path) {
  auto loaded = volume::loadMap(path);
  if (!loaded.ok()) return loaded.errorInfo();
  const auto& params = loaded.value().volume.params();
  const auto& mine = options_.volume;
  if (std::abs(params.voxel_size - mine.voxel_size) > 1e-9 || std::abs(params.truncation - mine.truncation) > 1e-9)
    return makeError(ErrorCode::kInvalidArgument,
                     path.string() + ": map has voxel size " + std::to_string(params.voxel_size) +
                         " m and truncation " + std::to_string(params.truncation) + " m; this server runs with " +
                         std::to_string(mine.voxel_size) + " m / " + std::to_string(mine.truncation) +
                         " m (start it with the map's values)");
  if (params.label_rule != mine.label_rule)
    return makeError(ErrorCode::kInvalidArgument,
                     path.string() + ": map fuses labels with the '" + volume::labelRuleName(params.label_rule) +
                         "' rule; this server runs '" + volume::labelRuleName(mine.label_rule) +
                         "' (start it with --label-rule " + volume::labelRuleName(params.label_rule) + ")");
  std::unique_lock lock(mutex_);
  // Whoever derives state from the map's changes (the distance field) sees everything change.
  loaded.value().volume.continueRevisionsFrom(volume_.revision());
  volume_ = std::move(loaded.value().volume);
  tracker_.reset();  // tracking restarts from the poses the next frames carry
  ++revision_;
  lock.unlock();
  if (on_change_) on_change_();
  return Status::Ok();
}

void Mapper::reset() {
  {
    std::unique_lock lock(mutex_);
    volume_.clear();
    tracker_.reset();
    ++revision_;
  }
  if (on_change_) on_change_();
}

std::shared_ptr<const volume::LabeledVolume> Mapper::snapshot() const {
  constexpr std::size_t kCopies = 2;
  std::lock_guard snapshot_lock(snapshot_mutex_);
  std::shared_lock lock(mutex_);
  if (!copies_.empty() && snapshot_revision_ == revision_) return copies_.back();
  // Only this list holds an idle copy, and only snapshot() hands copies out: no query can be
  // reading it while it changes.
  const auto idle =
      std::find_if(copies_.begin(), copies_.end(), [](const auto& copy) { return copy.use_count() == 1; });
  std::shared_ptr<volume::LabeledVolume> copy;
  if (idle != copies_.end()) {
    copy = std::move(*idle);
    copies_.erase(idle);
    copy->catchUpWith(volume_);
  } else {
    copy = std::make_shared<volume::LabeledVolume>(volume_.deepCopy());
  }
  copies_.push_back(copy);
  // The oldest copy is still being read: its queries keep it alive until they end.
  if (copies_.size() > kCopies) copies_.erase(copies_.begin());
  snapshot_revision_ = revision_;
  return copy;
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
