#include <cmath>
#include <limits>
#include <string>

#include "semfuse/wire/image_message.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

// One set of layer bits: the wire's (srv.idl) is the C++ one (core/raycast_layers.hpp).
static_assert(kDepthLayer == semfuse_srv_dds__Raycast_Request_Constants_LAYER_DEPTH);
static_assert(kNormalsLayer == semfuse_srv_dds__Raycast_Request_Constants_LAYER_NORMALS);
static_assert(kLabelsLayer == semfuse_srv_dds__Raycast_Request_Constants_LAYER_LABELS);
static_assert(kConfidenceLayer == semfuse_srv_dds__Raycast_Request_Constants_LAYER_CONFIDENCE);
static_assert(kColorLayer == semfuse_srv_dds__Raycast_Request_Constants_LAYER_COLOR);
static_assert(kAllLayers == (kDepthLayer | kNormalsLayer | kLabelsLayer | kConfidenceLayer | kColorLayer));

namespace {

// Each layer's place in the reply, its encoding on the wire and its type once decoded.
struct LayerField {
  const char* name;
  sensor_msgs_msg_dds__Image_ semfuse_srv_dds__Raycast_Response_::*wire;
  cv::Mat RaycastImages::*image;
  const char* encoding;
  int type;
};
constexpr LayerField kLayerFields[] = {
    {"depth", &semfuse_srv_dds__Raycast_Response_::depth, &RaycastImages::depth, "32FC1", CV_32FC1},
    {"normals", &semfuse_srv_dds__Raycast_Response_::normals, &RaycastImages::normals, "32FC3", CV_32FC3},
    {"labels", &semfuse_srv_dds__Raycast_Response_::labels, &RaycastImages::labels, "16UC1", CV_16UC1},
    {"confidence", &semfuse_srv_dds__Raycast_Response_::confidence, &RaycastImages::confidence, "32FC1", CV_32FC1},
    {"color", &semfuse_srv_dds__Raycast_Response_::color, &RaycastImages::color, "rgb8", CV_8UC3},
};

// decodeReply and takeReply: `take` hands the pixel buffers over instead of copying them.
template <class WireReply>
Result<ServiceReply<RaycastImages>> decodeImages(WireReply& wire, bool take) {
  return detail::decodeReplyWith<RaycastImages>(wire, [&]() -> Result<RaycastImages> {
    RaycastImages images;
    for (const LayerField& layer : kLayerFields) {
      auto& message = wire.*layer.wire;
      Result<cv::Mat> image = cv::Mat();
      if constexpr (std::is_const_v<WireReply>) {
        image = decodeImageMessage(message);
      } else {
        image = take ? takeImageMessage(message) : decodeImageMessage(message);
      }
      if (!image) return makeError(std::string(layer.name) + ": " + image.error());
      const cv::Mat& mat = image.value();
      if (!mat.empty() && mat.type() != layer.type) {
        return makeError(std::string(layer.name) + ": " + typeName(mat.type()) + " image, expected " +
                         typeName(layer.type));
      }
      images.*layer.image = std::move(image).value();
    }
    return images;
  });
}

}  // namespace

void RaycastCodec::encodeRequest(const Request& request, WireRequest& out) {
  poseToRowMajor(request.camera_to_world, out.camera_to_world);
  const PinholeIntrinsics& k = request.intrinsics;
  out.intrinsics = {static_cast<uint32_t>(k.width), static_cast<uint32_t>(k.height), k.fx, k.fy, k.cx, k.cy};
  out.layers = request.layers;
  out.max_range = request.max_range;
}

Result<RaycastRequest> RaycastCodec::decodeRequest(const WireRequest& wire) {
  constexpr uint32_t kMaxSide = static_cast<uint32_t>(std::numeric_limits<int>::max());
  if (wire.intrinsics.width > kMaxSide || wire.intrinsics.height > kMaxSide) {
    return makeError("raycast: image size " + std::to_string(wire.intrinsics.width) + "x" +
                     std::to_string(wire.intrinsics.height) + " is beyond any image");
  }
  RaycastRequest request;
  request.camera_to_world = poseFromRowMajor(wire.camera_to_world);
  request.intrinsics = {static_cast<int>(wire.intrinsics.width),
                        static_cast<int>(wire.intrinsics.height),
                        wire.intrinsics.fx,
                        wire.intrinsics.fy,
                        wire.intrinsics.cx,
                        wire.intrinsics.cy};
  request.layers = wire.layers;
  request.max_range = wire.max_range;
  return request;
}

void RaycastCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  for (const LayerField& layer : kLayerFields)
    fillImageMessage(out.*layer.wire, reply.value.*layer.image, layer.encoding);
}

Result<ServiceReply<RaycastImages>> RaycastCodec::decodeReply(const WireReply& wire) {
  return decodeImages(wire, false);
}

Result<ServiceReply<RaycastImages>> RaycastCodec::takeReply(WireReply& wire) { return decodeImages(wire, true); }

}  // namespace semfuse::wire
