#include "mapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <spdlog/spdlog.h>

#include "semfuse/tracking/volume_field.hpp"
#include "semfuse/volume/free_space.hpp"
#include "semfuse/volume/instance_integration.hpp"

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

namespace {
// The map as the tracker reads it: held for each alignment only, ahead of a waiting writer (and
// between an integration's batches), so that a pose never waits for a query or a whole frame, and
// the rest of tracking (pyramids, image alignment, keypoints) leaves the map to the fusion thread.
class LockedMapField final : public tracking::SdfField {
 public:
  // truncation: the server's, which a load keeps (Mapper::load refuses a map with another).
  LockedMapField(const volume::LabeledVolume& volume, WriterFirstMutex& mutex, float truncation)
      : field_(volume), mutex_(mutex), truncation_(truncation) {}
  float truncation() const override { return truncation_; }
  std::unique_ptr<tracking::SdfSampler> makeSampler() const override { return field_.makeSampler(); }
  void beginReading() const override { mutex_.lock_shared_ahead(); }
  void endReading() const override { mutex_.unlock_shared(); }

 private:
  tracking::VolumeField field_;
  WriterFirstMutex& mutex_;
  float truncation_;
};
}  // namespace

Result<tracking::TrackedFrame> Mapper::choosePose(const Frame& frame, TrackOutcome& outcome) {
  const auto start = std::chrono::steady_clock::now();
  const LockedMapField field(volume_, mutex_, static_cast<float>(options_.volume.truncation));
  Result<tracking::TrackedFrame> tracked = tracker_.track(frame, field, framesIntegrated() == 0);
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

// Long enough for the fusion thread to integrate one frame under any load; should it not (it is
// stuck), the frames go on and are tracked against what the map holds.
constexpr std::chrono::seconds kFirstFrameWait{2};

Result<PosedFrame> Mapper::track(Frame frame) {
  const uint64_t epoch = epoch_.load();
  std::unique_lock<std::mutex> empty_map;  // pose-less tracking one frame at a time while the map is empty
  if (!frame.camera_to_world) {
    std::unique_lock lock(first_frame_mutex_);
    first_frame_done_.wait_for(lock, kFirstFrameWait, [this] { return !first_frame_pending_; });
    if (framesIntegrated() == 0) empty_map = std::move(lock);
  }
  PosedFrame posed;
  auto tracked = choosePose(frame, posed.outcome);
  if (!tracked.ok()) return tracked.errorInfo();
  if (tracked.value().status == tracking::TrackingStatus::kInitialized && empty_map.owns_lock())
    first_frame_pending_ = true;
  posed.tracked = std::move(tracked).value();
  posed.frame = std::move(frame);
  posed.frame.camera_to_world.reset();
  if (posed.outcome.posed()) posed.frame.camera_to_world = posed.outcome.camera_to_world;
  posed.map_epoch = epoch;
  return posed;
}

void Mapper::firstFrameDone() {
  {
    std::lock_guard lock(first_frame_mutex_);
    if (!first_frame_pending_) return;
    first_frame_pending_ = false;
  }
  first_frame_done_.notify_all();
}

Result<volume::IntegrationStats> Mapper::integrate(const PosedFrame& posed, const Segmentation* segmentation) {
  if (!posed.frame.camera_to_world)
    return makeError("frame " + posed.frame.camera_id + "/" + std::to_string(posed.frame.seq) +
                     " has no pose to integrate at");
  Result<volume::IntegrationStats> stats = volume::IntegrationStats{};
  {
    std::unique_lock lock(mutex_);
    // Tracking reads between batches: a pose waits for a part of the frame, not all of it.
    stats = volume::integrate(volume_, posed.frame, segmentation, [this] { mutex_.admitReadersAhead(); });
    if (stats.ok() && segmentation)
      fuseInstances(posed.frame.depth, *segmentation, posed.frame.intrinsics, *posed.frame.camera_to_world);
    frames_integrated_ = volume_.framesIntegrated();
    // The frame passed the same checks in integrate(): this cannot fail on its input.
    if (stats.ok() && options_.observe_free_space)
      static_cast<void>(volume::observeFreeSpace(volume_, posed.frame.depth, posed.frame.intrinsics,
                                                 *posed.frame.camera_to_world, options_.free_space_stride));
  }
  firstFrameDone();
  if (!stats.ok()) return stats;
  if (on_change_) on_change_();
  tracker_.integrated(posed.frame, posed.tracked);
  return stats;
}

void Mapper::abandon(const PosedFrame& /*frame*/) { firstFrameDone(); }

void Mapper::fuseInstances(const cv::Mat& depth, const Segmentation& segmentation, const PinholeIntrinsics& intrinsics,
                           const Pose& camera_to_world) {
  if (segmentation.instances.empty()) return;  // a class-only segmenter
  auto fused = volume::integrateInstances(volume_, depth, segmentation.labels, segmentation.instances, intrinsics,
                                          camera_to_world);
  // The codec checked the instance map against its labels, which have just gone in at this depth
  // and pose: a failure here is a bug, not bad input.
  if (!fused) {
    spdlog::error("instances of {}/{} not fused: {}", segmentation.camera_id, segmentation.frame_seq, fused.error());
    return;
  }
  const volume::InstanceStats& s = fused.value();
  spdlog::debug("instances of {}/{}: {} segments, {} matched, {} new", segmentation.camera_id, segmentation.frame_seq,
                s.segments, s.matched, s.created);
}

Result<FrameOutcome> Mapper::integrateFrame(const Frame& frame, const Segmentation* segmentation) {
  auto posed = track(frame);
  if (!posed.ok()) return posed.errorInfo();
  FrameOutcome outcome;
  static_cast<TrackOutcome&>(outcome) = posed.value().outcome;
  if (!outcome.posed()) return outcome;
  const auto start = std::chrono::steady_clock::now();
  auto stats = integrate(posed.value(), segmentation);
  outcome.integrate_ms = millisecondsSince(start);
  if (!stats.ok()) return stats.errorInfo();
  outcome.stats = stats.value();
  outcome.integrated = true;
  return outcome;
}

Result<volume::IntegrationStats> Mapper::integrateSegmentation(const HistoryEntry& frame,
                                                               const Segmentation& segmentation) {
  std::unique_lock lock(mutex_);
  auto stats = volume::integrateLabels(volume_, frame.depth, segmentation.labels, segmentation.confidence,
                                       frame.intrinsics, frame.camera_to_world);
  if (stats.ok()) fuseInstances(frame.depth, segmentation, frame.intrinsics, frame.camera_to_world);
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
  frames_integrated_ = volume_.framesIntegrated();
  ++epoch_;
  lock.unlock();
  firstFrameDone();
  if (on_change_) on_change_();
  return Status::Ok();
}

void Mapper::reset() {
  {
    std::unique_lock lock(mutex_);
    volume_.clear();
    tracker_.reset();
    frames_integrated_ = 0;
    ++epoch_;
  }
  firstFrameDone();
  if (on_change_) on_change_();
}

std::shared_ptr<const volume::LabeledVolume> Mapper::snapshot() const {
  constexpr std::size_t kCopies = 2;
  std::lock_guard snapshot_lock(snapshot_mutex_);
  std::shared_lock lock(mutex_);
  if (!copies_.empty() && snapshot_revision_ == volume_.revision()) return copies_.back();
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
  snapshot_revision_ = volume_.revision();
  return copy;
}

uint64_t Mapper::snapshotBytes() const {
  std::lock_guard snapshot_lock(snapshot_mutex_);  // no copy is caught up meanwhile
  uint64_t bytes = 0;
  for (const auto& copy : copies_) bytes += copy->memoryBytes();
  return bytes;
}

Mapper::Size Mapper::size() const {
  std::shared_lock lock(mutex_);
  return {volume_.allocatedVoxels(), volume_.allocatedLeaves(), volume_.observedVoxels(), volume_.memoryBytes(),
          volume_.framesIntegrated()};
}

uint64_t Mapper::framesIntegrated() const { return frames_integrated_.load(); }

uint64_t Mapper::revision() const {
  std::shared_lock lock(mutex_);
  return volume_.revision();
}

}  // namespace semfuse::server
