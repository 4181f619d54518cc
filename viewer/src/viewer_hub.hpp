#pragma once
// ViewerHub: what the browsers see, kept in step with the map. It is the MapFollower's listener
// (every changed or removed block goes to every open page as a binary message, page_messages.hpp)
// and the WebServer's handlers: a page that opens gets the legend, every block the follower holds
// and the cameras' trajectories, taken under the follower's lock so that nothing between that
// copy and the next change is lost or sent twice. The main thread calls tick(): the server's
// status and the poses it published go to the pages, and the pages' clicks are answered with
// labels_at at the clicked point and a raycast from the page's view (all MapClient calls stay on
// that one thread).
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "page_messages.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/client/map_follower.hpp"
#include "web_server.hpp"

namespace semfuse::viewer {

class ViewerHub {
 public:
  ViewerHub(client::MapFollower& follower, client::MapClient& map, LabelLegend fallback_legend);

  // For WebServer; they refer to this hub, which must outlive the server.
  WebServer::Handlers handlers();
  // The follower's listener (its thread).
  void onChange(const client::MapFollowerChange& change);
  // Main thread: waits up to `wait` for clicks to answer, then sends what is due.
  void tick(std::chrono::milliseconds wait);

  FollowerCounters counters() const;

 private:
  void opened(const std::shared_ptr<WebSocketSession>& session);
  void closed(const WebSocketSession* session);
  void received(const std::shared_ptr<WebSocketSession>& session, const std::string& text);
  void broadcast(const std::shared_ptr<const std::string>& message, bool binary);
  std::string statusNow() const;

  client::MapFollower& follower_;
  client::MapClient& map_;

  mutable std::mutex mutex_;  // guards the members below
  LabelLegend legend_;
  bool server_legend_ = false;
  std::set<std::shared_ptr<WebSocketSession>> sessions_;
  std::vector<TrackedPose> trajectory_;  // integrated poses, each camera's path, bounded
  std::optional<ServerStatus> status_;

  // What a page asked: labels_at at a point, or a raycast from a view.
  struct Click {
    std::weak_ptr<WebSocketSession> session;
    bool raycast = false;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Pose camera_to_world = Pose::Identity();
    PinholeIntrinsics intrinsics;
    float max_range = 0.0F;
  };
  void answer(const Click& click);
  std::condition_variable clicked_;
  std::deque<Click> clicks_;

  std::chrono::steady_clock::time_point last_status_{};
};

}  // namespace semfuse::viewer
