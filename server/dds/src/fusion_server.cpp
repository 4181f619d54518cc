#include "fusion_server.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/volume/volume_param_table.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "semfuse/wire/status_codec.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {
namespace {

// Cyclone reads CYCLONEDDS_URI when the first participant is created: set it first.
dds_domainid_t prepareDds(const ServerConfig& config) {
  if (!config.dds_profile.empty()) {
    const std::filesystem::path profile = std::filesystem::absolute(config.dds_profile);
    if (!std::filesystem::exists(profile))
      throw std::runtime_error("--dds-profile " + config.dds_profile + ": no such file");
    setenv("CYCLONEDDS_URI", ("file://" + profile.string()).c_str(), 1);
  }
  return static_cast<dds_domainid_t>(config.domain_id);
}

// Configuration errors end the server before it serves (main reports them).
template <class T>
T valueOrThrow(Result<T> result) {
  if (!result) throw std::runtime_error(result.error());
  return std::move(result).value();
}

MapperOptions mapperOptions(const ServerConfig& config, const LabelLegend& legend) {
  MapperOptions options;
  options.volume = valueOrThrow(serverVolumeParams(config, legend));
  options.legend = legend;
  options.refine_given_poses = config.refine_given_poses;
  options.tracker.color_weight = config.track_color_weight;
  options.observe_free_space = config.esdf.enabled;
  options.free_space_stride =
      std::max(1, config.esdf.field.stride(options.volume.voxel_size, options.volume.truncation));
  return options;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

FusionServer::FusionServer(ServerConfig config)
    : config_(std::move(config)),
      legend_(valueOrThrow(serverLegend(config_))),
      participant_(prepareDds(config_)),
      frames_(config_.queue_per_camera, frameQueueWait(config_), kBacklogTimePerMaxWait * frameQueueWait(config_)),
      pose_topic_(participant_, dds::topics::kPoses),
      status_topic_(participant_, dds::topics::kStatus),
      legend_topic_(participant_, dds::topics::kLabels),
      pose_writer_(pose_topic_, dds::qos::poses()),
      status_writer_(status_topic_, dds::qos::status()),
      legend_writer_(legend_topic_, dds::qos::legend()) {
  // TBB's workers run the fusion's parallel work: they start here, at the map's priority, before
  // the query threads that run below it exist (thread_priority.hpp).
  startTbbWorkers();
  mapper_ = std::make_unique<Mapper>(mapperOptions(config_, legend_));

  if (!config_.map_file.empty() && std::filesystem::exists(config_.map_file)) {
    if (Status loaded = mapper_->load(config_.map_file); !loaded)
      throw std::runtime_error("cannot resume from --map " + config_.map_file + ": " + loaded.error() +
                               " (move the file away to start a new map)");
    const auto size = mapper_->size();
    spdlog::info("resumed map {}: {} frames, {} observed voxels", config_.map_file, size.frames_integrated,
                 size.observed_voxels);
  }

  if (config_.esdf.enabled) {
    if (Status ok = validateEsdfConfig(config_.esdf, config_.volume.voxel_size, config_.volume.truncation); !ok)
      throw std::runtime_error(ok.error());
    distance_field_ = std::make_unique<DistanceField>(*mapper_, config_.esdf.field);
    distance_field_->recordTimesIn(state_.stages);
    mapper_->setChangeListener([field = distance_field_.get()] { field->notify(); });
    occupancy_publisher_ = std::make_unique<OccupancyPublisher>(participant_, *distance_field_, config_.esdf);
  }

  FusionLimits fusion = config_.fusion;
  // --max-queue-wait 0: no frame is passed over anywhere, neither for tracking nor integration.
  fusion.integrate_every_frame = config_.max_queue_wait_s <= 0.0;
  fusion_ = std::make_unique<FusionLoop>(*mapper_, frames_, state_, fusion,
                                         [this](const PosedFrame& frame) { frameTracked(frame); });
  ingest_ = std::make_unique<Ingest>(participant_, frames_, *fusion_, state_, legend_);
  if (config_.ros.enabled) ros_ingest_ = std::make_unique<RosIngest>(participant_, config_.ros, frames_, state_);
  if (config_.map_updates.rate_hz > 0) {
    if (Status ok = validateMapUpdateConfig(config_.map_updates, config_.volume.voxel_size, config_.volume.truncation);
        !ok)
      throw std::runtime_error(ok.error());
    map_access_ = std::make_unique<MapperAccess>(*mapper_);
    try {
      map_updates_ = std::make_unique<MapUpdatePublisher>(participant_, *map_access_, config_.map_updates, legend_,
                                                          config_.ros.world_frame);
      map_updates_->updater().recordTimesIn(state_.stages);
    } catch (const dds::DdsError& e) {
      // E.g. DDS Security permissions written before the live mesh: the map is served without it.
      spdlog::error("map updates off: {}", e.what());
      state_.errors.record("map_updates", e.what());
    }
  }
  services_ = std::make_unique<Services>(
      participant_, config_, *mapper_, *fusion_, state_, [this] { return snapshot(); },
      [this](const std::string& path) { return saveMap(path); }, distance_field_.get(),
      map_updates_ ? &map_updates_->updater() : nullptr);
}

FusionServer::~FusionServer() { stop(); }

// Why this order:
// 1. Input first: the DDS and ROS 2 readers stop, so nothing new enters the queues or the inbox
//    while the fusion thread drains them.
// 2. The fusion thread takes no more admin tasks: a load or reset that comes in from now on gets
//    UNAVAILABLE at once ("shutting down"); one already posted still runs. Were tasks taken until
//    the thread ends, one posted just after would never run, and its service thread, which the
//    services' stop below joins, would wait out its 60 s timeout. A load or reset at this point
//    would also change the map the final save writes under the client's feet.
// 3. The fusion thread finishes the queued frames, segmentations and tasks (at most 5 s) and
//    ends. The services keep answering queries meanwhile.
// 4. The services stop: each finishes the request in hand (none can be waiting on the fusion
//    thread any more) and answers those still waiting UNAVAILABLE (dds::RpcServer::stop). The
//    map updates' thread stops before them (map_blocks only reads its store); with --esdf the
//    occupancy publisher stops before them too, and the distance field's thread after.
// run() then saves the map and publishes a last status; the DDS entities (writers, topics,
// participant) go last, as members, after everything that writes with them has stopped.
void FusionServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  if (ingest_) ingest_->stop();
  if (ros_ingest_) ros_ingest_->stop();
  if (fusion_) {
    fusion_->closeTasks();
    fusion_->drain(std::chrono::seconds(5));
    fusion_->stop();
  }
  if (map_updates_) map_updates_->stop();
  if (occupancy_publisher_) occupancy_publisher_->stop();
  services_.reset();
  // The field goes after the services that read it; nothing writes the map any more.
  if (distance_field_) distance_field_->stop();
}

int FusionServer::run() {
  auto encoded_legend = wire::encodeLegend(legend_);
  if (Status ok = legend_writer_.write(encoded_legend.msg()); !ok) spdlog::warn("legend: {}", ok.error());

  if (map_updates_) map_updates_->start();
  if (distance_field_) distance_field_->start();
  if (occupancy_publisher_) occupancy_publisher_->start();
  fusion_->start();
  ingest_->start();
  if (ros_ingest_) ros_ingest_->start();
  spdlog::info("serving on domain {}: voxel {} m, truncation {} m, legend '{}' ({} labels){}", config_.domain_id,
               config_.volume.voxel_size, config_.volume.truncation, legend_.name, legend_.labels.size(),
               config_.map_file.empty() ? "" : ", map " + config_.map_file);
  spdlog::debug("map parameters: {}",
                mapper_->read([](const volume::LabeledVolume& v) { return volume::volumeParamsText(v.params()); }));

  using namespace std::chrono_literals;
  auto last_status = std::chrono::steady_clock::now() - 1h;
  auto last_autosave = std::chrono::steady_clock::now();
  uint64_t published_changes = ~0ull;
  while (!stop_requested_) {
    std::this_thread::sleep_for(50ms);
    const double since_status = secondsSince(last_status);
    // Once a period, and on change (at most 10 times a second).
    if (since_status >= config_.status_period_s || (state_.changeCount() != published_changes && since_status >= 0.1)) {
      published_changes = state_.changeCount();
      publishStatus();
      last_status = std::chrono::steady_clock::now();
    }
    if (!config_.map_file.empty() && config_.autosave_period_s > 0 &&
        secondsSince(last_autosave) >= config_.autosave_period_s) {
      last_autosave = std::chrono::steady_clock::now();
      if (mapper_->revision() > 0) static_cast<void>(saveMap(config_.map_file));
    }
  }

  spdlog::info("shutting down: finishing queued frames");
  stop();
  int exit_code = 0;
  if (!config_.map_file.empty()) {
    if (Status saved = saveMap(config_.map_file); !saved) exit_code = 1;
  }
  publishStatus();
  const auto s = snapshot();
  spdlog::info(
      "frames: {} received, {} posed ({} integrated, {} skipped), {} lost; segmentations: {} received, {} "
      "integrated",
      s.frames_received, s.frames_posed, s.frames_integrated, s.frames_skipped, s.frames_lost, s.segmentations_received,
      s.segmentations_integrated);
  return exit_code;
}

Status FusionServer::saveMap(const std::string& path) {
  if (path.empty())
    return makeError(ErrorCode::kInvalidArgument, "no map file: start the server with --map FILE or give a path");
  std::lock_guard lock(save_mutex_);
  const auto start = std::chrono::steady_clock::now();
  volume::MapExtraMetadata extra{{"server_id", config_.server_id}};
  Status saved = mapper_->save(path, extra);
  last_save_ok_ = saved.ok();
  last_save_ = std::chrono::steady_clock::now();
  saved_once_ = true;
  if (!saved) {
    state_.errors.record("save", saved.error());
    spdlog::error("saving {} failed: {} (the previous file is intact)", path, saved.error());
  } else {
    spdlog::info("saved {} in {:.0f} ms", path, secondsSince(start) * 1000.0);
  }
  state_.touch();
  return saved;
}

// On a tracking thread, as soon as the frame's pose is known (the threads start after the services
// exist and stop before they go). The view is recorded before the pose goes out: a client that
// queries the objects once it has the pose finds the frame among those that saw them.
void FusionServer::frameTracked(const PosedFrame& frame) {
  if (frame.outcome.posed()) services_->recordView(frame.frame, frame.outcome.camera_to_world);
  publishPose(frame);
}

void FusionServer::publishPose(const PosedFrame& frame) {
  const TrackOutcome& outcome = frame.outcome;
  TrackedPose pose;
  pose.camera_id = frame.frame.camera_id;
  pose.seq = frame.frame.seq;
  pose.stamp = frame.frame.stamp;
  pose.frame_id = "world";
  pose.state = outcome.pose_state;
  pose.posed = outcome.posed();
  pose.camera_to_world = outcome.camera_to_world;
  pose.inlier_ratio = outcome.inlier_ratio;
  pose.residual = outcome.residual;
  pose.iterations = outcome.iterations;
  pose.track_ms = static_cast<float>(outcome.track_ms);
  auto encoded = wire::encodeTrackedPose(pose);
  if (Status ok = pose_writer_.write(encoded.msg()); !ok) spdlog::debug("pose: {}", ok.error());
  if (ros_ingest_) ros_ingest_->publishPose(frame.frame, outcome);
}

void FusionServer::publishStatus() {
  dds::Sample<semfuse_msg_dds__ServerStatus_> sample;
  wire::encodeServerStatus(snapshot(), wire::stampNow(), *sample);
  if (Status ok = status_writer_.write(*sample); !ok) spdlog::debug("status: {}", ok.error());
}

ServerStatus FusionServer::snapshot() const {
  ServerStatus s;
  s.server_id = config_.server_id;
  s.version = SEMFUSE_VERSION;
  s.uptime_s = secondsSince(started_);
  s.frames_received = state_.frames_received;
  s.frames_posed = state_.frames_posed;
  s.frames_integrated = state_.frames_integrated;
  s.frames_skipped = state_.frames_skipped;
  s.frames_lost = state_.frames_lost;
  s.segmentations_received = state_.segmentations_received;
  s.segmentations_integrated = state_.segmentations_integrated;
  for (const auto& c : state_.dropped.snapshot()) s.dropped.push_back({c.reason, c.camera_id, c.count});
  for (const auto& c : state_.rejected.snapshot()) s.rejected.push_back({c.reason, c.camera_id, c.count});
  s.queued_frames = static_cast<uint32_t>(frames_.size() + fusion_->framesAwaitingIntegration());
  s.pending_segmentations = static_cast<uint32_t>(fusion_->pendingSegmentations());
  s.history_frames = static_cast<uint32_t>(fusion_->historyFrames());
  s.voxel_size = config_.volume.voxel_size;
  s.truncation = config_.volume.truncation;
  // The field first: it never reports more than the map it follows.
  if (distance_field_) s.distance_field_revision = distance_field_->revision();
  s.map_revision = mapper_->revision();
  const auto size = mapper_->size();
  s.allocated_voxels = size.allocated_voxels;
  s.allocated_blocks = size.allocated_blocks;
  s.map_bytes = size.memory_bytes;
  s.snapshot_bytes = mapper_->snapshotBytes();
  s.rss_bytes = currentRssBytes();
  const auto now = std::chrono::steady_clock::now();
  for (const auto& [id, a] : state_.cameras()) {
    const float age = static_cast<float>(std::chrono::duration<double>(now - a.last_frame_time).count());
    CameraStatus camera;
    camera.camera_id = id;
    camera.tracking_state = a.tracking_state;
    camera.last_seq = a.last_seq;
    camera.frames_received = a.frames_received;
    camera.frames_posed = a.frames_posed;
    camera.frames_integrated = a.frames_integrated;
    camera.frames_skipped = a.frames_skipped;
    camera.frames_lost = a.frames_lost;
    camera.frame_rate_hz = static_cast<float>(a.rate_hz);
    camera.last_frame_age_s = age;
    camera.stale = age > config_.camera_stale_after_s;
    camera.lost_reason = a.lost_reason;
    camera.frames_since_lost = a.frames_since_lost;
    camera.relocalisations = a.relocalisations;
    s.cameras.push_back(std::move(camera));
  }
  for (const auto& e : state_.errors.snapshot())
    s.last_errors.push_back({std::chrono::duration<double>(e.time.time_since_epoch()).count(), e.source, e.message});
  s.map_file = config_.map_file;
  s.stages = state_.stages.summary();
  std::lock_guard lock(save_mutex_);
  s.last_save_ok = last_save_ok_;
  s.last_save_age_s = saved_once_ ? secondsSince(last_save_) : -1.0;
  return s;
}

}  // namespace semfuse::server
