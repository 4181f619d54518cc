#include "map_update_publisher.hpp"

#include <vector>

#include <spdlog/spdlog.h>

#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/wire/map_update_codecs.hpp"

namespace semfuse::server {

MapUpdatePublisher::MapUpdatePublisher(const dds::Participant& participant, const MapAccess& map,
                                       const MapUpdateConfig& config, const LabelLegend& legend,
                                       const std::string& frame_id)
    : config_(config),
      legend_(legend),
      update_topic_(participant, dds::topics::kMapUpdates),
      marker_topic_(participant, dds::topics::kMapMarkers),
      cloud_topic_(participant, dds::topics::kMapCloud),
      update_writer_(update_topic_, dds::qos::mapUpdates()),
      marker_writer_(marker_topic_, dds::qos::mapUpdates()),
      cloud_writer_(cloud_topic_, dds::qos::mapCloud()),
      updater_(map, config, *this) {
  style_.frame_id = frame_id;
  style_.coloring = config.marker_colors == "rgb" ? wire::VertexColoring::kRgb : wire::VertexColoring::kLabel;
}

MapUpdatePublisher::~MapUpdatePublisher() { updater_.stop(); }

bool MapUpdatePublisher::listening() const {
  return update_writer_.matchedReaders() > 0 || marker_writer_.matchedReaders() > 0 ||
         (config_.cloud_period_s > 0 && cloud_writer_.matchedReaders() > 0);
}

void MapUpdatePublisher::publish(const MapUpdate& update) {
  if (update_writer_.matchedReaders() > 0) {
    const wire::EncodedMapUpdate encoded = wire::encodeMapUpdate(update);
    if (Status ok = update_writer_.write(encoded.msg()); !ok) spdlog::debug("map update: {}", ok.error());
  }
  style_.stamp = update.stamp;
  if (marker_writer_.matchedReaders() > 0) publishMarkers(update);
  // The cloud after the last part, when the surface changed and the period has passed.
  if (update.part + 1 == update.parts && config_.cloud_period_s > 0 && cloud_writer_.matchedReaders() > 0)
    publishCloud(update.header);
}

int32_t MapUpdatePublisher::markerId(const BlockOrigin& origin) {
  const auto [it, added] = marker_ids_.try_emplace(origin, static_cast<int32_t>(marker_ids_.size()));
  return it->second;
}

void MapUpdatePublisher::publishMarkers(const MapUpdate& update) {
  const bool cleared = update.part == 0 && update.header.cleared_revision != marked_cleared_revision_;
  marked_cleared_revision_ = update.header.cleared_revision;
  dds::Sample<visualization_msgs_msg_dds__MarkerArray_> sample;
  auto& markers = sample->markers;
  dds::resizeSequence(markers, update.blocks.size() + (cleared ? 1 : 0));
  std::size_t i = 0;
  if (cleared) wire::fillDeleteAllMarker(markers._buffer[i++], style_);
  for (const MeshBlock& block : update.blocks)
    wire::fillBlockMarker(markers._buffer[i++], block, markerId(block.origin), update.header.voxel_size, legend_,
                          style_);
  if (Status ok = marker_writer_.write(*sample); !ok) spdlog::debug("map markers: {}", ok.error());
}

void MapUpdatePublisher::publishCloud(const MapBlocksHeader& header) {
  const auto now = std::chrono::steady_clock::now();
  if (header.revision == cloud_revision_ || now - last_cloud_ < std::chrono::duration<double>(config_.cloud_period_s))
    return;
  dds::Sample<sensor_msgs_msg_dds__PointCloud2_> sample;
  updater_.store().visitBlocks([&](const std::vector<const MeshBlock*>& blocks) {
    wire::fillSurfaceCloud(*sample, blocks, header.voxel_size, legend_, style_);
  });
  if (Status ok = cloud_writer_.write(*sample); !ok) spdlog::debug("map cloud: {}", ok.error());
  last_cloud_ = now;
  cloud_revision_ = header.revision;
}

}  // namespace semfuse::server
