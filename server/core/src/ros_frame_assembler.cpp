#include "ros_frame_assembler.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace semfuse::server {
namespace {
double secondsBetween(Stamp a, Stamp b) {
  return static_cast<double>(a.sec - b.sec) + (static_cast<double>(a.nanosec) - static_cast<double>(b.nanosec)) * 1e-9;
}
}  // namespace

std::optional<RosFrameAssembler::Drop> RosFrameAssembler::addDepth(uint64_t seq, Stamp stamp,
                                                                   const std::string& frame_id, cv::Mat depth,
                                                                   Clock::time_point now) {
  std::optional<Drop> dropped;
  if (depth_.size() >= options_.pending_depth) {
    dropped = Drop{ros_reason::kDepthQueueFull, depth_.front().seq,
                   fmt::format("{} depth images already waiting for colour, CameraInfo or tf", depth_.size())};
    depth_.pop_front();
  }
  depth_.push_back({seq, stamp, frame_id, std::move(depth), now, {}});
  return dropped;
}

std::optional<RosFrameAssembler::Drop> RosFrameAssembler::addColor(Stamp stamp, cv::Mat color) {
  std::optional<Drop> dropped;
  if (color_.size() >= options_.pending_color) {
    dropped = Drop{ros_reason::kColorUnpaired, 0, "colour image list full: no depth image within the tolerance"};
    color_.pop_front();
  }
  auto at = std::upper_bound(color_.begin(), color_.end(), stamp.seconds(),
                             [](double t, const PendingColor& c) { return t < c.stamp.seconds(); });
  color_.insert(at, {stamp, std::move(color)});
  return dropped;
}

bool RosFrameAssembler::pairColor(PendingDepth& d, std::vector<Drop>& drops) {
  auto best = color_.end();
  double best_dt = options_.pair_tolerance_s;
  for (auto it = color_.begin(); it != color_.end(); ++it) {
    const double dt = std::abs(secondsBetween(it->stamp, d.stamp));
    if (dt <= best_dt) {
      best_dt = dt;
      best = it;
    }
  }
  if (best == color_.end()) return false;
  d.color = std::move(best->color);
  // Depth leaves in order, so colour images older than the one taken can pair with nothing.
  const auto taken = static_cast<size_t>(best - color_.begin());
  for (size_t i = 0; i < taken; ++i) {
    drops.push_back({ros_reason::kColorUnpaired, 0,
                     fmt::format("colour at {:.3f} s: no depth image within {:.3f} s", color_.front().stamp.seconds(),
                                 options_.pair_tolerance_s)});
    color_.pop_front();
  }
  color_.pop_front();
  return true;
}

RosFrameAssembler::Step RosFrameAssembler::advance(PendingDepth& d, bool timed_out, const PoseLookup& lookup,
                                                   std::vector<Frame>& frames, std::vector<Drop>& drops) {
  const double waited = options_.wait_s;
  if (!intrinsics_) {
    if (!timed_out) return Step::kWait;
    drops.push_back({ros_reason::kNoCameraInfo, d.seq, fmt::format("no CameraInfo within {:.2f} s", waited)});
    return Step::kDone;
  }
  if (intrinsics_->width != d.depth.cols || intrinsics_->height != d.depth.rows) {
    drops.push_back({"invalid_frame", d.seq,
                     fmt::format("depth image {}x{} but CameraInfo {}x{}", d.depth.cols, d.depth.rows,
                                 intrinsics_->width, intrinsics_->height),
                     true});
    return Step::kDone;
  }
  if (options_.expect_color && d.color.empty() && !pairColor(d, drops)) {
    if (!timed_out) return Step::kWait;
    drops.push_back({ros_reason::kNoColor, d.seq,
                     fmt::format("no colour image within {:.3f} s of depth stamp {:.3f} s in {:.2f} s",
                                 options_.pair_tolerance_s, d.stamp.seconds(), waited)});
    return Step::kDone;
  }
  if (!d.color.empty() && d.color.size() != d.depth.size()) {
    drops.push_back({"invalid_frame", d.seq,
                     fmt::format("colour image {}x{} is not registered to depth {}x{}", d.color.cols, d.color.rows,
                                 d.depth.cols, d.depth.rows),
                     true});
    return Step::kDone;
  }

  Frame frame;
  frame.camera_id = options_.camera_id;
  frame.seq = d.seq;
  frame.stamp = d.stamp;
  frame.frame_id = options_.camera_frame.empty() ? d.frame_id : options_.camera_frame;
  frame.intrinsics = *intrinsics_;
  if (options_.use_tf) {
    auto pose = frame.frame_id.empty() ? Result<Pose>(makeError("the depth image has no frame_id"))
                                       : lookup(frame.frame_id, d.stamp);
    if (pose.ok()) {
      frame.camera_to_world = pose.value();
      had_world_pose_ = true;
    } else if (!timed_out) {
      return Step::kWait;
    } else if (!had_world_pose_) {
      // Tracking from nothing would start a world frame of its own that tf poses contradict later.
      drops.push_back(
          {ros_reason::kNoTf, d.seq, fmt::format("no world pose within {:.2f} s: {}", waited, pose.error())});
      return Step::kDone;
    }  // else: integrated without a pose, tracked from this camera's last one
  }
  frame.depth = std::move(d.depth);
  frame.color = std::move(d.color);
  frames.push_back(std::move(frame));
  return Step::kDone;
}

void RosFrameAssembler::poll(Clock::time_point now, const PoseLookup& lookup, std::vector<Frame>& frames,
                             std::vector<Drop>& drops) {
  const auto wait = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.wait_s));
  while (!depth_.empty()) {
    PendingDepth& d = depth_.front();
    const bool timed_out = now - d.arrived >= wait;
    if (advance(d, timed_out, lookup, frames, drops) == Step::kWait) break;
    depth_.pop_front();
  }
  // Colour images that waited longer than any depth image may wait are of no use any more.
  while (!color_.empty() && depth_.empty() && color_.size() > options_.pending_color / 2) {
    drops.push_back({ros_reason::kColorUnpaired, 0, "colour image with no depth image"});
    color_.pop_front();
  }
}

}  // namespace semfuse::server
