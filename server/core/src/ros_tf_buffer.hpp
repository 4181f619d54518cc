#pragma once
// A small tf buffer: the transforms received on /tf (time-stamped, kept for a bounded time per
// frame) and /tf_static (timeless), and the lookup of one frame in another at a time stamp,
// through any chain of parents (map -> odom -> base_link -> camera_link -> camera_optical).
// Between two stamps of an edge the transform is interpolated (lerp + slerp), as tf2 does; a
// stamp outside an edge's history is not extrapolated.
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::server {

class TfBuffer {
 public:
  explicit TfBuffer(double history_s = 10.0) : history_s_(history_s) {}

  // parent_T_child: the pose of `child` in `parent` (what a TransformStamped carries).
  // Returns an error for an empty or self-referencing frame id.
  Status add(const std::string& parent, const std::string& child, const Pose& parent_T_child, Stamp stamp,
             bool is_static);

  // target_T_source at `stamp`: the pose of frame `source` in frame `target`. The error says
  // which edge is missing or out of its time range.
  Result<Pose> lookup(const std::string& target, const std::string& source, Stamp stamp) const;

 private:
  struct Sample {
    double t;
    Pose parent_T_child;
  };
  struct Edge {
    std::string parent;
    bool is_static = false;
    std::deque<Sample> samples;  // by time; one sample for static edges
  };
  // root_T_frame at t, and the root reached, walking up the parents.
  Result<std::pair<std::string, Pose>> toRoot(const std::string& frame, double t) const;
  static Result<Pose> edgeAt(const std::string& child, const Edge& edge, double t);

  double history_s_;
  mutable std::mutex mutex_;
  std::map<std::string, Edge> edges_;  // by child frame
};

}  // namespace semfuse::server
