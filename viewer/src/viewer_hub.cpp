#include "viewer_hub.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include <spdlog/spdlog.h>

#include "page_messages.hpp"

namespace semfuse::viewer {
namespace {

constexpr std::size_t kMaxTrajectoryPoses = 50000;
constexpr auto kStatusPeriod = std::chrono::milliseconds(500);

std::shared_ptr<const std::string> shared(std::string text) {
  return std::make_shared<const std::string>(std::move(text));
}

}  // namespace

ViewerHub::ViewerHub(client::MapFollower& follower, client::MapClient& map, LabelLegend fallback_legend)
    : follower_(follower), map_(map), legend_(std::move(fallback_legend)) {}

WebServer::Handlers ViewerHub::handlers() {
  WebServer::Handlers h;
  h.opened = [this](const std::shared_ptr<WebSocketSession>& s) { opened(s); };
  h.closed = [this](const WebSocketSession* s) { closed(s); };
  h.received = [this](const std::shared_ptr<WebSocketSession>& s, const std::string& text) { received(s, text); };
  h.api = [this](const std::string& name) -> std::optional<std::string> {
    if (name == "status") return statusNow();
    if (name == "legend") {
      std::lock_guard lock(mutex_);
      return legendJson(legend_);
    }
    return std::nullopt;
  };
  return h;
}

void ViewerHub::opened(const std::shared_ptr<WebSocketSession>& session) {
  // Under the follower's lock: the listener cannot run between this copy and the registration.
  follower_.visit([&](const client::MapFollowerState& state) {
    std::lock_guard lock(mutex_);
    session->send(shared(legendJson(legend_)), false);
    session->send(shared(clearedMessage()), true);
    for (const auto& [origin, block] : state.blocks)
      session->send(shared(blockMessage(block, state.header.voxel_size)), true);
    session->send(shared(posesJson(trajectory_)), false);
    sessions_.insert(session);
  });
  session->send(shared(statusNow()), false);
  spdlog::info("viewer: a page connected ({} open)", counters().browsers);
}

void ViewerHub::closed(const WebSocketSession* session) {
  std::lock_guard lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
    if (it->get() == session) {
      sessions_.erase(it);
      break;
    }
}

// When the user clicks the surface the page sends "labels_at X Y Z" (metres, world frame) and
// "raycast W H FX FY CX CY RANGE M0 .. M15" (its view: intrinsics, the farthest metres to look
// (0: the server's default) and camera-to-world, column-major, camera looking along +z with y down).
void ViewerHub::received(const std::shared_ptr<WebSocketSession>& session, const std::string& text) {
  constexpr int kMaxRaycastSide = 1024;
  std::istringstream in(text);
  std::string command;
  Click click;
  click.session = session;
  bool ok = static_cast<bool>(in >> command);
  if (ok && command == "labels_at") {
    ok = static_cast<bool>(in >> click.point.x() >> click.point.y() >> click.point.z()) && click.point.allFinite();
  } else if (ok && command == "raycast") {
    click.raycast = true;
    PinholeIntrinsics& k = click.intrinsics;
    Eigen::Matrix4d m;
    ok = static_cast<bool>(in >> k.width >> k.height >> k.fx >> k.fy >> k.cx >> k.cy >> click.max_range) &&
         std::isfinite(click.max_range) && click.max_range >= 0.0F;
    for (int i = 0; ok && i < 16; ++i) ok = static_cast<bool>(in >> m(i % 4, i / 4));
    ok = ok && k.width > 0 && k.height > 0 && k.width <= kMaxRaycastSide && k.height <= kMaxRaycastSide &&
         m.allFinite() && k.fx > 0 && k.fy > 0;
    if (ok) click.camera_to_world.matrix() = m;
  } else {
    ok = false;
  }
  if (!ok) {
    session->send(shared(errorJson("request", "not understood: " + text.substr(0, 80))), false);
    return;
  }
  std::lock_guard lock(mutex_);
  if (clicks_.size() >= 16) clicks_.pop_front();  // a page clicking faster than the server answers
  clicks_.push_back(std::move(click));
  clicked_.notify_one();
}

void ViewerHub::onChange(const client::MapFollowerChange& change) {
  std::vector<std::shared_ptr<const std::string>> messages;
  if (change.started_over) messages.push_back(shared(clearedMessage()));
  for (const BlockOrigin& origin : change.removed) messages.push_back(shared(removedMessage(origin)));
  const double voxel_size = change.state->header.voxel_size;
  for (const MeshBlock* block : change.changed) messages.push_back(shared(blockMessage(*block, voxel_size)));
  for (const auto& message : messages) broadcast(message, true);
}

void ViewerHub::broadcast(const std::shared_ptr<const std::string>& message, bool binary) {
  std::lock_guard lock(mutex_);
  for (const auto& session : sessions_) session->send(message, binary);
}

void ViewerHub::tick(std::chrono::milliseconds wait) {
  std::optional<Click> click;
  {
    std::unique_lock lock(mutex_);
    clicked_.wait_for(lock, wait, [this] { return !clicks_.empty(); });
    if (!clicks_.empty()) {
      click = std::move(clicks_.front());
      clicks_.pop_front();
    }
  }
  if (click) answer(*click);

  if (auto legend = map_.latestLegend()) {
    std::unique_lock lock(mutex_);
    if (!server_legend_ || legend->name != legend_.name || legend->labels.size() != legend_.labels.size()) {
      legend_ = *legend;
      server_legend_ = true;
      const auto message = shared(legendJson(legend_));
      for (const auto& session : sessions_) session->send(message, false);
    }
  }

  std::vector<TrackedPose> poses = map_.takePoses(std::chrono::milliseconds(0));
  if (!poses.empty()) {
    {
      std::lock_guard lock(mutex_);
      for (const TrackedPose& pose : poses)
        if (pose.posed) trajectory_.push_back(pose);
      if (trajectory_.size() > kMaxTrajectoryPoses) {
        // Keep every other pose of the older half: the path stays, its detail thins out.
        std::vector<TrackedPose> thinned;
        for (std::size_t i = 0; i < trajectory_.size(); ++i)
          if (i >= trajectory_.size() / 2 || i % 2 == 0) thinned.push_back(trajectory_[i]);
        trajectory_ = std::move(thinned);
      }
    }
    broadcast(shared(posesJson(poses)), false);
  }

  const auto now = std::chrono::steady_clock::now();
  if (now - last_status_ >= kStatusPeriod) {
    last_status_ = now;
    if (auto status = map_.latestStatus()) {
      std::lock_guard lock(mutex_);
      status_ = std::move(status);
    }
    broadcast(shared(statusNow()), false);
  }
}

void ViewerHub::answer(const Click& click) {
  auto session = click.session.lock();
  if (!session) return;
  LabelLegend legend;
  {
    std::lock_guard lock(mutex_);
    legend = legend_;
  }
  if (click.raycast) {
    auto view = map_.raycast(click.camera_to_world, click.intrinsics, kDepthLayer | kLabelsLayer,
                             std::chrono::seconds(10), click.max_range);
    if (!view) return session->send(shared(errorJson("raycast", view.error())), false);
    return session->send(shared(raycastMessage(view.value(), legend)), true);
  }
  auto samples = map_.labelsAt({click.point}, std::chrono::seconds(5));
  if (!samples || samples.value().empty())
    return session->send(shared(errorJson("labels_at", samples ? "no answer" : samples.error())), false);
  const VoxelSample& sample = samples.value().front();
  // The object there: the smallest instance of that label whose box (grown by a few centimetres:
  // the point lies on the surface, the box around voxel centres) holds the point.
  std::optional<ObjectInstance> object;
  if (sample.observed && sample.label != kUnlabeled) {
    if (auto objects = map_.objects(sample.label, 0, std::chrono::seconds(10))) {
      constexpr double kMargin = 0.05;
      for (const ObjectInstance& o : objects.value()) {
        const bool inside = ((click.point - o.bbox_min).array() >= -kMargin).all() &&
                            ((o.bbox_max - click.point).array() >= -kMargin).all();
        if (inside && (!object || o.voxel_count < object->voxel_count)) object = o;
      }
    }
  }
  session->send(shared(labelsAtJson(click.point, sample, legend, object ? &*object : nullptr)), false);
}

FollowerCounters ViewerHub::counters() const {
  FollowerCounters c;
  follower_.visit([&](const client::MapFollowerState& state) {
    c.blocks = state.blocks.size();
    c.vertices = state.vertexCount();
    c.revision = state.covered_revision;
  });
  const client::MapFollowerStats stats = follower_.stats();
  c.updates = stats.updates;
  c.catch_ups = stats.catch_ups;
  c.gaps = stats.gaps;
  std::lock_guard lock(mutex_);
  c.browsers = sessions_.size();
  return c;
}

std::string ViewerHub::statusNow() const {
  const FollowerCounters c = counters();
  std::lock_guard lock(mutex_);
  return statusJson(status_, c);
}

}  // namespace semfuse::viewer
