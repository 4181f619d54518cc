#include "ros_tf_buffer.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace semfuse::server {
namespace {
// A tf chain longer than this is a loop (tf forbids cycles; a bad publisher may still make one).
constexpr int kMaxChainLength = 64;

Pose interpolate(const Pose& a, const Pose& b, double s) {
  Pose out = Pose::Identity();
  const Eigen::Quaterniond qa(a.rotation()), qb(b.rotation());
  out.linear() = qa.slerp(s, qb).toRotationMatrix();
  out.translation() = (1.0 - s) * a.translation() + s * b.translation();
  return out;
}
}  // namespace

Status TfBuffer::add(const std::string& parent, const std::string& child, const Pose& parent_T_child, Stamp stamp,
                     bool is_static) {
  if (parent.empty() || child.empty()) return makeError("transform with an empty frame id");
  if (parent == child) return makeError(fmt::format("transform from '{}' to itself", child));
  std::lock_guard lock(mutex_);
  Edge& edge = edges_[child];
  if (edge.parent != parent) edge.samples.clear();  // re-parented: the old history no longer applies
  edge.parent = parent;
  edge.is_static = is_static;
  const double t = stamp.seconds();
  if (is_static) {
    edge.samples.assign(1, {t, parent_T_child});
    return {};
  }
  // Usually in order; an out-of-order sample is inserted where it belongs.
  auto at =
      std::upper_bound(edge.samples.begin(), edge.samples.end(), t, [](double v, const Sample& s) { return v < s.t; });
  edge.samples.insert(at, {t, parent_T_child});
  const double newest = edge.samples.back().t;
  while (edge.samples.size() > 2 && edge.samples.front().t < newest - history_s_) edge.samples.pop_front();
  return {};
}

Result<Pose> TfBuffer::edgeAt(const std::string& child, const Edge& edge, double t) {
  if (edge.samples.empty()) return makeError(fmt::format("no transform {} -> {}", edge.parent, child));
  if (edge.is_static || edge.samples.size() == 1) {
    if (edge.is_static || std::abs(edge.samples.front().t - t) < 1e-6) return edge.samples.front().parent_T_child;
  }
  const auto& s = edge.samples;
  if (t < s.front().t - 1e-6 || t > s.back().t + 1e-6) {
    return makeError(fmt::format("transform {} -> {} at {:.3f} s is outside its history [{:.3f}, {:.3f}] s",
                                 edge.parent, child, t, s.front().t, s.back().t));
  }
  auto next = std::lower_bound(s.begin(), s.end(), t, [](const Sample& a, double v) { return a.t < v; });
  if (next == s.end()) return s.back().parent_T_child;
  if (next == s.begin() || std::abs(next->t - t) < 1e-9) return next->parent_T_child;
  const auto prev = std::prev(next);
  const double span = next->t - prev->t;
  return interpolate(prev->parent_T_child, next->parent_T_child, span > 0 ? (t - prev->t) / span : 0.0);
}

Result<std::pair<std::string, Pose>> TfBuffer::toRoot(const std::string& frame, double t) const {
  std::string current = frame;
  Pose root_T_frame = Pose::Identity();
  for (int depth = 0; depth < kMaxChainLength; ++depth) {
    const auto it = edges_.find(current);
    if (it == edges_.end()) return std::make_pair(current, root_T_frame);
    auto parent_T_current = edgeAt(current, it->second, t);
    if (!parent_T_current.ok()) return makeError(parent_T_current.error());
    root_T_frame = parent_T_current.value() * root_T_frame;
    current = it->second.parent;
  }
  return makeError(fmt::format("tf chain above '{}' is longer than {} frames (a loop?)", frame, kMaxChainLength));
}

Result<Pose> TfBuffer::lookup(const std::string& target, const std::string& source, Stamp stamp) const {
  if (target == source) return Pose(Pose::Identity());
  std::lock_guard lock(mutex_);
  const double t = stamp.seconds();
  auto source_chain = toRoot(source, t);
  if (!source_chain.ok()) return makeError(source_chain.error());
  auto target_chain = toRoot(target, t);
  if (!target_chain.ok()) return makeError(target_chain.error());
  if (source_chain.value().first != target_chain.value().first) {
    return makeError(fmt::format("no tf path from '{}' to '{}' (their trees end in '{}' and '{}')", target, source,
                                 target_chain.value().first, source_chain.value().first));
  }
  return Pose(target_chain.value().second.inverse() * source_chain.value().second);
}

}  // namespace semfuse::server
