#pragma once
// Turns separate ROS 2 streams (depth images, colour images, CameraInfo, tf) into the semfuse
// Frames the native ingest produces. Depth images leave in arrival order once they have their
// colour (the colour image with the closest stamp within a tolerance), intrinsics and, when tf
// is used, a world pose at their stamp. Everything is bounded: a depth image waits at most
// `wait`, at most `pending_depth` wait at once, `pending_color` colour images are kept, and each
// image given up is reported as a drop with its reason. No DDS here, so it is unit-tested alone.
#include <chrono>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::server {

// Reasons (in ServerStatus, beside the native ones) for ROS inputs given up before fusion.
namespace ros_reason {
inline constexpr const char* kDepthQueueFull = "ros_depth_queue_full";  // too many depth images waiting
inline constexpr const char* kNoColor = "ros_no_color";                 // no colour within the stamp tolerance
inline constexpr const char* kColorUnpaired = "ros_color_unpaired";     // colour image no depth image took
inline constexpr const char* kNoCameraInfo = "ros_no_camera_info";      // no CameraInfo received yet
inline constexpr const char* kNoTf = "ros_no_tf";                       // no world pose and none before to track from
}  // namespace ros_reason

class RosFrameAssembler {
 public:
  using Clock = std::chrono::steady_clock;

  struct Options {
    std::string camera_id = "ros";
    bool expect_color = true;
    double pair_tolerance_s = 0.02;
    double wait_s = 0.5;
    size_t pending_depth = 8;
    size_t pending_color = 16;
    bool use_tf = true;
    std::string camera_frame;  // "" = the depth image's frame id
  };

  // An image given up. `rejected` = malformed (counted as a rejection, not a drop).
  struct Drop {
    const char* reason;
    uint64_t seq = 0;  // the depth image's seq; 0 for colour images
    std::string message;
    bool rejected = false;
  };

  // world_T_camera for `camera_frame` at `stamp`, or why not (the transform may still arrive).
  using PoseLookup = std::function<Result<Pose>(const std::string& camera_frame, Stamp stamp)>;

  explicit RosFrameAssembler(Options options) : options_(std::move(options)) {}

  void setIntrinsics(const PinholeIntrinsics& intrinsics) { intrinsics_ = intrinsics; }
  // depth: CV_32FC1 metres. Returns the drop it caused when the waiting list was full.
  std::optional<Drop> addDepth(uint64_t seq, Stamp stamp, const std::string& frame_id, cv::Mat depth,
                               Clock::time_point now);
  // color: CV_8UC3 RGB. Returns the drop it caused when the colour list was full.
  std::optional<Drop> addColor(Stamp stamp, cv::Mat color);

  // Frames now complete, in seq order, and the images given up since the last call.
  void poll(Clock::time_point now, const PoseLookup& lookup, std::vector<Frame>& frames, std::vector<Drop>& drops);

  size_t pendingColor() const { return color_.size(); }

 private:
  struct PendingDepth {
    uint64_t seq;
    Stamp stamp;
    std::string frame_id;
    cv::Mat depth;
    Clock::time_point arrived;
    cv::Mat color;  // once paired
  };
  struct PendingColor {
    Stamp stamp;
    cv::Mat color;
  };
  enum class Step { kDone, kWait };
  // Tries to complete the oldest depth image: emits it, drops it, or says it must wait.
  Step advance(PendingDepth& d, bool timed_out, const PoseLookup& lookup, std::vector<Frame>& frames,
               std::vector<Drop>& drops);
  bool pairColor(PendingDepth& d, std::vector<Drop>& drops);

  Options options_;
  std::optional<PinholeIntrinsics> intrinsics_;
  std::deque<PendingDepth> depth_;
  std::deque<PendingColor> color_;  // in stamp order
  bool had_world_pose_ = false;     // once tf gave a pose, the tracker can bridge tf gaps
};

}  // namespace semfuse::server
