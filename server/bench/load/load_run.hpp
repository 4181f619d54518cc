#pragma once
// The load bench's scenario against a server that is already up (with --esdf): posed and tracked
// cameras streaming 7-Scenes frames, segmenters labelling some of them, query clients for
// raycast, labels_at, objects and distance at fixed rates and a map follower, all at once for
// the run's duration; then the server is drained and, with nothing else running, the raycast is
// timed through the server and in the library on the same map.
#include <sys/types.h>

#include <atomic>
#include <memory>
#include <vector>

#include "ingest/followed_updates.hpp"
#include "ingest/pose_collector.hpp"
#include "ingest/preloaded_frames.hpp"
#include "load_options.hpp"
#include "load_result.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/client/segmenter.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/writer.hpp"

namespace semfuse::bench::load {

class LoadRun {
 public:
  LoadRun(const LoadOptions& options, const ingest::Preloaded& data, dds_domainid_t domain);

  // `pid` is the server's process.
  Result<LoadResult> run(pid_t pid);

 private:
  Status connect();
  std::vector<std::unique_ptr<QueryLoop>> makeQueries(const std::atomic<std::size_t>& camera0_index);
  void showProgress(double elapsed_s);
  Result<client::ServerStatus> drain();

  const LoadOptions& options_;
  const ingest::Preloaded& data_;
  dds::Participant participant_;
  dds::Topic<ingest::FrameMsg> frame_topic_;
  client::MapClient map_;
  ingest::PoseCollector poses_;
  std::unique_ptr<ingest::FollowedUpdates> follower_;
  std::vector<std::unique_ptr<dds::Writer<ingest::FrameMsg>>> writers_;
  std::vector<std::unique_ptr<client::Segmenter>> segmenters_;
};

}  // namespace semfuse::bench::load
