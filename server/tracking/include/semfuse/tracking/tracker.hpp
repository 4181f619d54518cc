#pragma once
// The tracking of every camera of one map: the pose each frame is integrated at, or why it is
// not integrated.
//  - A frame with a pose is integrated at that pose (or, on request, at that pose refined by
//    alignment to the map).
//  - A frame without one is aligned to the map (depth to the TSDF, colour to the fused colour),
//    starting from the camera's motion prediction.
//  - The first pose-less frame of an empty map defines the world frame.
//  - A camera whose alignment cannot be trusted is lost: its frames are not integrated, and each
//    new frame is searched for among the keyframes the map has seen, until one is verified by
//    alignment. A camera that joins a map without a pose is placed the same way.
// A wrong pose must never reach the map: every pose that is integrated passed the quality tests.
//
// Threads: track() may run for several cameras at once (each camera's frames one at a time, in
// order), beside integrated() from the thread that writes the map, and beside reset(): a frame in
// flight then finishes on the state its camera had, which nothing keeps (the server discards such
// frames: they were tracked against a map that is gone).
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/tracking/image_pyramid.hpp"
#include "semfuse/tracking/keyframe_store.hpp"
#include "semfuse/tracking/keypoint_map.hpp"
#include "semfuse/tracking/rgbd_odometry.hpp"
#include "semfuse/tracking/sdf_field.hpp"
#include "semfuse/tracking/sdf_tracker.hpp"

namespace semfuse::tracking {

enum class GivenPosePolicy {
  kUseAsIs,  // trust the pose the frame carries
  kRefine,   // use it as the starting guess of an alignment (kept as is if the alignment fails)
};

enum class TrackingStatus {
  kInitialized,  // first frame of an empty map: placed at the initial pose, integrate it
  kGivenPose,    // the frame's own pose was used
  kRefined,      // the frame's own pose, refined by alignment
  kTracked,      // aligned to the map from the motion prediction
  kRelocalised,  // found again (or placed for the first time) by a keyframe and verified
  kLost,         // no pose that can be trusted: do not integrate
};
const char* toString(TrackingStatus status);

struct TrackedFrame {
  TrackingStatus status = TrackingStatus::kLost;
  // Set when status is kLost (or a refinement failed), and kDegenerate for a tracked frame whose
  // depth and colour constrained only some directions.
  LostReason lost_reason = LostReason::kNone;
  Pose pose = Pose::Identity();   // pose to integrate at; for a lost frame the last good pose
  Pose guess = Pose::Identity();  // where the alignment started
  TrackingQuality quality;        // of the alignment, when one ran
  // The image alignment the SDF alignment started from (to the last frame, or to a keyframe when
  // relocalising): the share of its points matched, 0 when none ran or it was not used.
  double image_matched = 0.0;
  // What integrated() needs to make the frame a keyframe once it is in the map: its small images
  // (when they were built for this frame) and the camera's typical agreement at the time.
  std::shared_ptr<const ImagePyramid> keyframe_images;
  std::optional<double> typical_agreement;
  bool shouldIntegrate() const { return status != TrackingStatus::kLost; }
};

// One camera as the server's status reports it.
struct CameraTrackingSummary {
  TrackingStatus last_status = TrackingStatus::kLost;
  bool lost = false;               // frames are not integrated until the camera is relocalised
  uint64_t frames = 0;             // frames tracked (any status)
  uint64_t lost_total = 0;         // frames not integrated for want of a pose
  uint64_t frames_since_lost = 0;  // frames of the current loss (0 while tracking)
  uint64_t relocalisations = 0;    // times the camera was found again (or placed) by a keyframe
};

struct TrackerConfig {
  TrackerParams alignment;
  OdometryParams odometry;
  KeyframeParams keyframes;
  KeypointParams keypoints;
  GivenPosePolicy given_pose = GivenPosePolicy::kUseAsIs;
  // Where the first pose-less frame of an empty map is placed (the world frame's origin).
  Pose initial_pose = Pose::Identity();

  // An image alignment (to the last frame, or to a keyframe) gives the SDF alignment its start
  // when the current image sees at least min_image_overlap of the reference's points and at
  // least min_odometry_matched of those agree in depth; otherwise the motion prediction and rest
  // are tried (tracking) or the keyframe is passed over (relocalisation).
  double min_image_overlap = 0.3;
  double min_odometry_matched = 0.6;

  // A pose is trusted when, besides the aligner's own tests, at least min_agreement of its points
  // agree with the map where the map was observed, and either
  //  - the SDF alignment started from an image alignment (to the last frame or to a keyframe)
  //    and corrected it by little: two independent alignments agree; or
  //  - the map confirms it on its own: at least confirm_min_inlier_ratio of the frame's points
  //    lie on the map's surfaces, and the agreement is at least confirm_min_agreement and within
  //    max_agreement_drop of the camera's recent median. A relocalised pose whose keypoints also
  //    agree (see below) needs only confirm_min_inlier_ratio_with_keypoints of the points.
  // A pose that slid into a wrong minimum (after a jump or a covered sensor) has neither: the last
  // frame's images are not seen again, and a wrong pose overlaps the map little or disagrees.
  // The floor is low because agreement depends on the scene: redkitchen's frames 180-200 agree at
  // 0.60-0.64 at poses that every other test confirms.
  double min_agreement = 0.45;
  // The image alignment works on 160x120 images: a pixel there is about 1.5 cm at 2 m.
  double max_image_correction_m = 0.03;
  double max_image_correction_rad = 0.035;  // 2 degrees
  double confirm_min_inlier_ratio = 0.6;
  // A camera that comes back to the map from new ground sees the map with part of its image (on
  // redkitchen 40-60 % of the points at the true pose). A scene that repeats its shape (a
  // symmetric room) can match that much at a wrong pose too; its texture does not. So a share
  // this low is enough only when the keyframes' keypoints matched to the frame land near their
  // pixels at the pose: at least min_keypoint_support of them within keypoint_support_px
  // (for 640 px wide images; generous, as colour and depth are registered only roughly on some
  // sensors). A wrong pose of the synthetic room explains 1; the true one 30-50.
  double confirm_min_inlier_ratio_with_keypoints = 0.4;
  int min_keypoint_support = 20;
  double keypoint_support_px = 20.0;
  double confirm_min_agreement = 0.75;
  double max_agreement_drop = 0.06;
  int agreement_history = 15;  // recent trusted frames the median is taken over

  // A camera that tracks may integrate this many frames in a row whose depth and colour leave some
  // directions free (a view of a wall or a floor), with those directions taken from where the
  // alignment started (the image alignment, or the motion prediction): half a second at 30 Hz,
  // over which the prediction drifts by millimetres. A longer view of one plane loses the camera.
  // Relocalisation never accepts such a pose.
  int max_partially_constrained_frames = 15;

  // Relocalisation: the nearest keyframes tried.
  std::size_t relocalisation_candidates = 5;
  // Relocalisation also matches the keyframes' ORB keypoints (keypoint_map.hpp), which find a
  // camera far from every keyframe's viewpoint; off, only the ferns' nearest keyframes are tried.
  bool keypoint_relocalisation = true;

  // Frames of a camera that carries poses are considered as keyframes every this many frames
  // (a camera that tracks is considered at every integrated frame).
  int given_pose_keyframe_interval = 10;
};

class Tracker {
 public:
  explicit Tracker(TrackerConfig config = {});
  ~Tracker();
  Tracker(const Tracker&) = delete;
  Tracker& operator=(const Tracker&) = delete;

  // Decides the pose of `frame` against the map seen through `field`. map_empty: nothing has been
  // integrated yet (a pose-less first frame then defines the world frame). Errors for malformed
  // frames (empty or wrongly typed depth, size not matching the intrinsics, non-finite or
  // non-rigid given pose), which leave every camera's state untouched.
  Result<TrackedFrame> track(const Frame& frame, const SdfField& field, bool map_empty);

  // The frame was integrated at tracked.pose: it may become a keyframe for relocalisation. Frames
  // tracked but never integrated (skipped under load) are simply not passed here.
  void integrated(const Frame& frame, const TrackedFrame& tracked);

  // The map was cleared or replaced: every camera starts over, every keyframe is forgotten.
  void reset();

  std::map<std::string, CameraTrackingSummary> cameras() const;
  // One camera's (all zero for a camera the tracker has not seen).
  CameraTrackingSummary camera(const std::string& camera_id) const;
  std::size_t keyframes() const;
  const TrackerConfig& config() const { return config_; }

 private:
  struct CameraState;
  std::shared_ptr<CameraState> stateOf(const std::string& camera_id);
  // track() for a valid frame (given: its rigid pose, if it carries one), on the calling thread.
  Result<TrackedFrame> trackCamera(const Frame& frame, const std::optional<Pose>& given, const SdfField& field,
                                   bool map_empty, CameraState& state);
  Result<TrackedFrame> trackWithoutPose(const Frame& frame, const SdfField& field, bool map_empty, CameraState& state);
  // Searches the keyframes (and `extra` starts) for the frame's pose; kRelocalised or kLost.
  Result<TrackedFrame> relocalise(const Frame& frame, const SdfField& field, CameraState& state,
                                  const std::vector<Pose>& extra, LostReason reason_if_not_found);
  // relocalise(), and a found pose is integrated only once the next frame confirms it.
  Result<TrackedFrame> relocaliseConfirmed(const Frame& frame, const SdfField& field, CameraState& state,
                                           const std::vector<Pose>& extra, LostReason reason_if_not_found);
  // Whether an alignment's pose may be integrated: `start` is where it began, image_matched the
  // share of points the image alignment behind that start matched (0 when none).
  // allow_partial: a pose that depth and colour constrain only in part may pass (tracking, within
  // the camera's budget of such frames; never relocalisation). keypoint_support: the keyframes'
  // keypoints the pose explains (relocalisation only).
  bool trusted(const Alignment& alignment, const Pose& start, double image_matched, const CameraState& state,
               bool allow_partial, int keypoint_support = 0) const;
  bool usableImageAlignment(const OdometryResult& odometry) const;

  TrackerConfig config_;
  // Where the map was seen from, shared by every camera: read by relocalisation, written by
  // integrated(). The keypoint map keeps its last search for explained(), so one user at a time.
  mutable std::mutex memory_mutex_;
  KeyframeStore keyframes_;
  KeypointMap keypoints_;  // of the keyframes, in the same order
  // Each camera's state, its aligner and image buffers included; the map's lookups under the
  // mutex, a state itself used by the one thread that tracks its camera.
  mutable std::mutex cameras_mutex_;
  std::map<std::string, std::shared_ptr<CameraState>> cameras_;
};

}  // namespace semfuse::tracking
