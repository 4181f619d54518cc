#include "semfuse/tracking/tracker.hpp"

#include <algorithm>
#include <deque>
#include <optional>
#include <string>

#include <tbb/task_arena.h>

#include "semfuse/core/camera_check.hpp"
#include "semfuse/tracking/depth_pyramid.hpp"
#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {

const char* toString(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kInitialized:
      return "initialized";
    case TrackingStatus::kGivenPose:
      return "given pose";
    case TrackingStatus::kRefined:
      return "refined";
    case TrackingStatus::kTracked:
      return "tracked";
    case TrackingStatus::kRelocalised:
      return "relocalised";
    case TrackingStatus::kLost:
      return "lost";
  }
  return "unknown";
}

// Everything the tracker remembers about one camera between its frames, and the buffers its
// frames are tracked with (each camera its own, so that cameras are tracked concurrently).
struct Tracker::CameraState {
  explicit CameraState(const TrackerParams& params) : aligner(params) {}

  // A frame is tracked on its caller's thread alone: at a few thousand points a level, splitting
  // a pass over cores costs more CPU than it saves time, and a thread waiting for its own
  // parallel work may pick up another's meanwhile (the server's integration). Cameras are
  // tracked in parallel instead.
  tbb::task_arena one_thread{1};
  SdfTracker aligner;                 // keeps its buffers between frames
  ImagePyramid current_images;        // of the frame being tracked
  bool placed = false;                // has a pose in the world frame (an integrated frame)
  Pose last_pose = Pose::Identity();  // last pose a frame was integrated at
  // Camera motion between the last two good frames, in the camera frame (T_prev^-1 T_last): the
  // constant-velocity model predicts the next pose as last_pose * velocity.
  Pose velocity = Pose::Identity();
  // Small images of the last integrated frame: the reference of the next frame's image alignment.
  ImagePyramid last_images;
  bool last_images_fresh = false;  // they are the images of the frame integrated last
  // A pose relocalisation found for an earlier frame and its images, not integrated: a later frame
  // relocalised on its own must land where the images' motion carries this pose.
  std::optional<Pose> candidate;
  ImagePyramid candidate_images;
  // Map agreement of the camera's recent trusted frames, whose median the next ones are held to.
  std::deque<double> agreements;
  int partial_run = 0;  // frames integrated in a row that depth and colour constrained only in part
  CameraTrackingSummary summary;

  Pose predictNext() const { return last_pose * velocity; }

  std::optional<double> typicalAgreement() const {
    if (agreements.size() < 5) return std::nullopt;
    std::vector<double> sorted(agreements.begin(), agreements.end());
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    return sorted[sorted.size() / 2];
  }

  void accept(const Pose& pose, TrackingStatus status) {
    // Velocity only from two consecutive good frames; after a lost frame (or the first) the model
    // restarts at rest rather than extrapolating across the gap.
    velocity = (placed && !summary.lost) ? last_pose.inverse() * pose : Pose::Identity();
    last_pose = pose;
    placed = true;
    if (status == TrackingStatus::kRelocalised) ++summary.relocalisations;
    candidate.reset();
    summary.lost = false;
    summary.frames_since_lost = 0;
    summary.last_status = status;
  }

  void lose() {
    ++summary.lost_total;
    ++summary.frames_since_lost;
    summary.lost = true;
    summary.last_status = TrackingStatus::kLost;
    velocity = Pose::Identity();
    last_images_fresh = false;
  }
};

namespace {

Result<Pose> rigidGivenPose(const Pose& pose) {
  if (Status status = checkRigidPose(pose); !status) return makeError("frame " + status.error());
  return orthonormalized(pose);
}

}  // namespace

Tracker::Tracker(TrackerConfig config)
    : config_(std::move(config)), keyframes_(config_.keyframes), keypoints_(config_.keypoints) {}
Tracker::~Tracker() = default;

std::shared_ptr<Tracker::CameraState> Tracker::stateOf(const std::string& camera_id) {
  std::lock_guard lock(cameras_mutex_);
  auto& slot = cameras_[camera_id];
  if (!slot) slot = std::make_shared<CameraState>(config_.alignment);
  return slot;
}

Result<TrackedFrame> Tracker::track(const Frame& frame, const SdfField& field, bool map_empty) {
  if (Status status = validateDepthImage(frame.depth, frame.intrinsics); !status) return makeError(status.error());
  std::optional<Pose> given;
  if (frame.camera_to_world) {
    Result<Pose> rigid = rigidGivenPose(*frame.camera_to_world);
    if (!rigid) return makeError(rigid.error());
    given = rigid.value();
  }
  const std::shared_ptr<CameraState> held = stateOf(frame.camera_id);  // alive through a reset()
  std::optional<Result<TrackedFrame>> out;
  held->one_thread.execute([&] { out = trackCamera(frame, given, field, map_empty, *held); });
  return std::move(*out);
}

Result<TrackedFrame> Tracker::trackCamera(const Frame& frame, const std::optional<Pose>& given, const SdfField& field,
                                          bool map_empty, CameraState& state) {
  const bool use_given = given && config_.given_pose == GivenPosePolicy::kUseAsIs;
  // A camera with poses needs its images only now and then, for keyframes.
  bool images_due =
      !use_given ||
      state.summary.frames % static_cast<uint64_t>(std::max(1, config_.given_pose_keyframe_interval)) == 0;
  if (images_due) {
    Status built = state.aligner.setFrame(frame.depth, frame.color, frame.intrinsics);
    // A frame that carries its pose needs no images to be integrated: one too small for the
    // pyramid just never becomes a keyframe.
    if (!built && !use_given) return makeError(built.error());
    if (built) state.current_images.build(state.aligner.pyramid());
    images_due = built.ok();
  }

  TrackedFrame out;
  if (use_given) {
    out.status = TrackingStatus::kGivenPose;
    out.pose = out.guess = *given;
  } else if (given) {
    out.guess = *given;
    Result<Alignment> aligned = state.aligner.align(field, {out.guess});
    if (!aligned) return makeError(aligned.error());
    out.quality = aligned.value().quality;
    out.lost_reason = aligned.value().lost_reason;
    // A given pose stays usable when its refinement is not trusted.
    out.status = aligned.value().ok() ? TrackingStatus::kRefined : TrackingStatus::kGivenPose;
    out.pose = aligned.value().ok() ? aligned.value().pose : out.guess;
  } else {
    Result<TrackedFrame> tracked = trackWithoutPose(frame, field, map_empty, state);
    if (!tracked) return tracked;
    out = tracked.value();
  }

  ++state.summary.frames;
  if (out.shouldIntegrate()) {
    state.accept(out.pose, out.status);
    const bool partial = out.status == TrackingStatus::kTracked && out.lost_reason == LostReason::kDegenerate;
    state.partial_run = partial ? state.partial_run + 1 : 0;
    state.last_images_fresh = images_due;
    if (images_due) std::swap(state.last_images, state.current_images);
    if (out.status == TrackingStatus::kTracked) {
      state.agreements.push_back(out.quality.observed_agreement);
      while (state.agreements.size() > static_cast<std::size_t>(std::max(1, config_.agreement_history)))
        state.agreements.pop_front();
    }
    // The keyframe candidate's own copy: the camera's buffers belong to its next frames by the
    // time the frame is integrated.
    if (images_due) out.keyframe_images = std::make_shared<const ImagePyramid>(state.last_images.cloneFrom(1));
    out.typical_agreement = state.typicalAgreement();
  } else {
    out.pose = state.last_pose;
    state.lose();
  }
  return out;
}

Result<TrackedFrame> Tracker::trackWithoutPose(const Frame& frame, const SdfField& field, bool map_empty,
                                               CameraState& state) {
  TrackedFrame out;
  if (!state.placed && map_empty) {
    out.status = TrackingStatus::kInitialized;
    out.pose = out.guess = orthonormalized(config_.initial_pose);
    return out;
  }
  // A camera the map has not placed yet, or one that lost its way, is searched for among the
  // keyframes; its last pose is tried too (a sensor covered for a moment, a camera at rest).
  if (!state.placed) return relocaliseConfirmed(frame, field, state, {}, LostReason::kNotPlaced);
  if (state.summary.lost) return relocaliseConfirmed(frame, field, state, {state.last_pose}, LostReason::kNotPlaced);

  // Start from the motion the images show since the last integrated frame: it follows changes of
  // speed and direction that the constant-velocity prediction misses, by several centimetres at
  // 30 Hz of handheld motion. Where the images cannot tell (too little of the last frame is seen
  // again), the prediction and rest are both tried.
  out.guess = orthonormalized(state.predictNext());
  std::vector<Pose> starts;
  if (state.last_images_fresh && !state.last_images.empty()) {
    const OdometryResult odometry =
        alignImages(state.last_images, state.current_images, state.velocity.inverse(), config_.odometry);
    out.image_matched = usableImageAlignment(odometry) ? odometry.matched_ratio : 0.0;
    if (usableImageAlignment(odometry))
      starts.push_back(orthonormalized(state.last_pose * odometry.current_from_reference.inverse()));
  }
  if (starts.empty()) {
    starts.push_back(out.guess);
    if (!state.velocity.isApprox(Pose::Identity())) starts.push_back(state.last_pose);
  } else {
    out.guess = starts.front();
  }
  Result<Alignment> aligned = state.aligner.align(field, starts);
  if (!aligned) return makeError(aligned.error());
  out.quality = aligned.value().quality;
  out.lost_reason = aligned.value().lost_reason;
  out.pose = aligned.value().pose;
  if (trusted(aligned.value(), starts[static_cast<std::size_t>(aligned.value().quality.start)],
              out.image_matched >= config_.min_odometry_matched && aligned.value().quality.start == 0
                  ? out.image_matched
                  : 0.0,
              state, /*allow_partial=*/true)) {
    // A partially constrained pose keeps kDegenerate as its reason: integrated, but worth knowing.
    out.status = TrackingStatus::kTracked;
    return out;
  }
  // Not trusted: the camera may have jumped (a dropped link, a kidnap) or the alignment slid into
  // a wrong minimum. The keyframes get a chance at once, with the tracked pose among the starts.
  const LostReason reason = aligned.value().ok() ? LostReason::kDisagreesWithMap : aligned.value().lost_reason;
  if (aligned.value().lost_reason == LostReason::kNoValidDepth) {
    out.status = TrackingStatus::kLost;
    return out;
  }
  return relocaliseConfirmed(frame, field, state, {aligned.value().pose, state.last_pose}, reason);
}

namespace {

// How far the SDF alignment moved the pose from where it started.
bool smallCorrection(const Pose& start, const Pose& result, double max_m, double max_rad) {
  const Pose correction = start.inverse() * result;
  return correction.translation().norm() <= max_m && rotationAngle(correction.linear()) <= max_rad;
}

}  // namespace

bool Tracker::usableImageAlignment(const OdometryResult& odometry) const {
  return odometry.overlap >= config_.min_image_overlap && odometry.matched_ratio >= config_.min_odometry_matched;
}

bool Tracker::trusted(const Alignment& alignment, const Pose& start, double image_matched, const CameraState& state,
                      bool allow_partial, int keypoint_support) const {
  // A large correction from the start (kDiverged) is no reason to doubt a pose on its own: a
  // relocalisation start from a keyframe may be far off. The agreement test below decides then.
  const bool diverged = alignment.lost_reason == LostReason::kDiverged;
  const bool partial = alignment.lost_reason == LostReason::kDegenerate && allow_partial &&
                       state.partial_run < config_.max_partially_constrained_frames;
  if (!alignment.ok() && !diverged && !partial) return false;
  const double agreement = alignment.quality.observed_agreement;
  if (agreement < config_.min_agreement) return false;
  // Two independent alignments that agree: the images (frame to frame, or to a keyframe) and the
  // depth and colour against the map. A pose that slid into a wrong minimum needs a large
  // correction from an image-alignment start, or had no such start.
  if (!diverged && image_matched >= config_.min_odometry_matched &&
      smallCorrection(start, alignment.pose, config_.max_image_correction_m, config_.max_image_correction_rad))
    return true;
  // Otherwise the map must confirm the pose on its own: most of the frame's points on the map's
  // surfaces (a wrong pose can agree well with the little of the map it overlaps), and as many of
  // the observed ones agreeing as in the camera's recent frames.
  const double min_inlier_ratio = keypoint_support >= config_.min_keypoint_support
                                      ? config_.confirm_min_inlier_ratio_with_keypoints
                                      : config_.confirm_min_inlier_ratio;
  if (alignment.quality.inlier_ratio < min_inlier_ratio) return false;
  const std::optional<double> typical = state.typicalAgreement();
  return agreement >= config_.confirm_min_agreement && (!typical || agreement >= *typical - config_.max_agreement_drop);
}

Result<TrackedFrame> Tracker::relocalise(const Frame& frame, const SdfField& field, CameraState& state,
                                         const std::vector<Pose>& extra, LostReason reason_if_not_found) {
  TrackedFrame out;
  out.status = TrackingStatus::kLost;
  out.lost_reason = reason_if_not_found;
  out.pose = state.last_pose;
  if (state.aligner.pyramid().points(0).empty()) {
    out.lost_reason = LostReason::kNoValidDepth;
    return out;
  }
  // Each near keyframe proposes the pose that aligns its images with the frame's.
  std::vector<Pose> starts;
  std::vector<double> matched;
  bool keypoints_tried = false;
  KeypointMatches keypoint_matches;  // what the keypoint search tried, to judge the pose by
  {
    const bool keypoints_wanted = config_.keypoint_relocalisation && !frame.color.empty();
    const FrameKeypoints keypoints =
        keypoints_wanted ? keypoints_.detect(frame.color, frame.depth, frame.intrinsics) : FrameKeypoints{};
    std::lock_guard memory(memory_mutex_);
    const std::vector<uint8_t> code = keyframes_.encode(state.current_images);
    for (const KeyframeMatch& match : keyframes_.nearest(code, config_.relocalisation_candidates)) {
      const Keyframe& keyframe = keyframes_.keyframe(match.index);
      const OdometryResult odometry =
          alignImages(keyframe.images, state.current_images, Pose::Identity(), config_.odometry);
      if (!usableImageAlignment(odometry)) continue;
      starts.push_back(orthonormalized(keyframe.camera_to_world * odometry.current_from_reference.inverse()));
      matched.push_back(odometry.matched_ratio);
    }
    // Keypoints matched one by one reach viewpoints the ferns' whole-image comparison does not.
    keypoints_tried = config_.keypoint_relocalisation && keypoints_.keyframes() > 0;
    if (keypoints_tried) {
      if (const std::optional<KeypointPose> found = keypoints_.locate(keypoints, frame.intrinsics)) {
        starts.push_back(found->camera_to_world);
        matched.push_back(0.0);
      }
      keypoint_matches = keypoints_.lastMatches();
    }
  }
  for (const Pose& pose : extra) {
    starts.push_back(pose);
    matched.push_back(0.0);
  }
  if (starts.empty()) return out;
  Result<Alignment> aligned = state.aligner.align(field, starts);
  if (!aligned) return makeError(aligned.error());
  out.quality = aligned.value().quality;
  out.image_matched = matched[static_cast<std::size_t>(aligned.value().quality.start)];
  out.guess = starts[static_cast<std::size_t>(aligned.value().quality.start)];
  out.pose = aligned.value().pose;
  const int keypoint_support =
      !keypoints_tried ? 0
                       : keypoint_matches.explainedBy(out.pose, frame.intrinsics,
                                                      config_.keypoint_support_px * frame.intrinsics.width / 640.0);
  if (!trusted(aligned.value(), out.guess, out.image_matched, state, /*allow_partial=*/false, keypoint_support)) {
    if (!aligned.value().ok()) out.lost_reason = aligned.value().lost_reason;
    return out;
  }
  out.status = TrackingStatus::kRelocalised;
  out.lost_reason = LostReason::kNone;
  return out;
}

Result<TrackedFrame> Tracker::relocaliseConfirmed(const Frame& frame, const SdfField& field, CameraState& state,
                                                  const std::vector<Pose>& extra, LostReason reason_if_not_found) {
  Result<TrackedFrame> found = relocalise(frame, field, state, extra, reason_if_not_found);
  if (!found || found.value().status != TrackingStatus::kRelocalised) return found;
  // One relocalised frame can pass every test at a pose a few centimetres off, in a shallow
  // minimum of a scene that repeats or is seen only in part. Two frames relocalised each from
  // their own starts that agree with the images' motion between them are not off by chance.
  TrackedFrame out = found.value();
  // Found within the aligner's basin of the camera's last pose (a sensor covered for a moment, a
  // camera at rest): as trustworthy as a frame tracked from there, which needs no second frame.
  const TrackerParams& basin = config_.alignment;
  if (state.placed && smallCorrection(state.last_pose, out.pose, basin.max_correction_fraction * field.truncation(),
                                      basin.max_correction_rad))
    return out;
  if (state.candidate) {
    const OdometryResult motion =
        alignImages(state.candidate_images, state.current_images, Pose::Identity(), config_.odometry);
    if (usableImageAlignment(motion) &&
        smallCorrection(*state.candidate * motion.current_from_reference.inverse(), out.pose,
                        config_.max_image_correction_m, config_.max_image_correction_rad))
      return out;
  }
  state.candidate = out.pose;
  state.candidate_images = state.current_images.cloneFrom(0);
  out.status = TrackingStatus::kLost;
  out.lost_reason = LostReason::kUnconfirmed;
  return out;
}

void Tracker::integrated(const Frame& frame, const TrackedFrame& tracked) {
  if (!tracked.shouldIntegrate() || !tracked.keyframe_images) return;
  // Only frames whose pose is beyond doubt become keyframes: a wrong keyframe would relocalise a
  // camera to a wrong pose later.
  if (tracked.lost_reason == LostReason::kDegenerate) return;
  if (tracked.status == TrackingStatus::kTracked) {
    const std::optional<double>& typical = tracked.typical_agreement;
    if (typical && tracked.quality.observed_agreement < *typical - 0.5 * config_.max_agreement_drop) return;
  }
  std::unique_lock memory(memory_mutex_);
  if (!keyframes_.addIfNovel(frame.camera_id, tracked.pose, *tracked.keyframe_images) ||
      !config_.keypoint_relocalisation)
    return;
  // The detection (milliseconds) without the lock: a relocalising camera need not wait for it.
  memory.unlock();
  FrameKeypoints keypoints = keypoints_.detect(frame.color, frame.depth, frame.intrinsics);
  memory.lock();
  keypoints_.add(keypoints, tracked.pose);
}

void Tracker::reset() {
  std::scoped_lock lock(cameras_mutex_, memory_mutex_);
  cameras_.clear();
  keyframes_.clear();
  keypoints_.clear();
}

std::size_t Tracker::keyframes() const {
  std::lock_guard lock(memory_mutex_);
  return keyframes_.size();
}

// A camera's summary is written by the thread that tracks it: read from that thread.
CameraTrackingSummary Tracker::camera(const std::string& camera_id) const {
  std::lock_guard lock(cameras_mutex_);
  auto found = cameras_.find(camera_id);
  return found == cameras_.end() ? CameraTrackingSummary{} : found->second->summary;
}

std::map<std::string, CameraTrackingSummary> Tracker::cameras() const {
  std::lock_guard lock(cameras_mutex_);
  std::map<std::string, CameraTrackingSummary> out;
  for (const auto& [id, state] : cameras_) out[id] = state->summary;
  return out;
}

}  // namespace semfuse::tracking
