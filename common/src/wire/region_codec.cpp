#include "semfuse/wire/service_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void RegionCodec::encodeRequest(const Request& box, WireRequest& out) {
  out.min = detail::toPoint(box.min);
  out.max = detail::toPoint(box.max);
}

Result<Box> RegionCodec::decodeRequest(const WireRequest& wire) {
  return Box{detail::fromPoint(wire.min), detail::fromPoint(wire.max)};
}

void RegionCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  const RegionSummary& summary = reply.value;
  detail::encodeSequence(out.histogram, summary.histogram, [](const LabelArea& area) {
    return semfuse_msg_dds__LabelCount_{area.label, area.surface_voxels, area.area_m2};
  });
  out.observed_voxels = summary.observed_voxels;
  out.occupied_voxels = summary.occupied_voxels;
  out.free_voxels = summary.free_voxels;
  out.occupancy = summary.occupancy;
}

Result<ServiceReply<RegionSummary>> RegionCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&]() -> Result<RegionSummary> {
    auto histogram =
        detail::decodeSequence("region histogram", wire.histogram, [](const semfuse_msg_dds__LabelCount_& c) {
          return LabelArea{c.label, c.surface_voxels, c.area_m2};
        });
    if (!histogram) return makeError(histogram.error());
    RegionSummary summary;
    summary.histogram = std::move(histogram).value();
    summary.observed_voxels = wire.observed_voxels;
    summary.occupied_voxels = wire.occupied_voxels;
    summary.free_voxels = wire.free_voxels;
    summary.occupancy = wire.occupancy;
    return summary;
  });
}

}  // namespace semfuse::wire
