// Fuzz target: PNG, JPEG and RVL payloads of a frame, as raw bytes. Input layout:
//   byte 0     what the payload is: 0 colour "png", 1 colour "jpeg", 2 depth "png16", 3 depth "rvl"
//   bytes 1-4  the frame's declared width and height (uint16 little endian each)
//   the rest   the payload
// The payload goes into an otherwise valid Frame_ and through wire::decodeFrame, the path the
// server takes: PNG header check, OpenCV's decoders, the RVL decoder, decoded size and type
// against the frame. An RVL payload the decoder accepts must be the encoder's own bytes for it.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "fuzz_support.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/rvl_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 5) return 0;
  const int kind = data[0] % 4;
  const bool depth_payload = kind >= 2;
  const uint32_t width = data[1] | (uint32_t{data[2]} << 8);
  const uint32_t height = data[3] | (uint32_t{data[4]} << 8);
  std::vector<uint8_t> payload(data + 5, data + size);

  semfuse_msg_dds__Frame_ msg{};
  std::string camera_id = "fuzz", frame_id = "camera";
  std::string depth_encoding = kind == 2 ? "png16" : kind == 3 ? "rvl" : "16UC1";
  std::string color_encoding = kind == 0 ? "png" : kind == 1 ? "jpeg" : "";
  msg.camera_id = camera_id.data();
  msg.header.frame_id = frame_id.data();
  msg.intrinsics = {width, height, 500.0, 500.0, width / 2.0, height / 2.0};
  msg.depth_encoding = depth_encoding.data();
  msg.color_encoding = color_encoding.data();
  msg.depth_scale = 0.001f;
  // The other image is raw and of the right size, so only the payload under test can fail. Above
  // a million pixels it is left empty (the frame is refused before the payload is looked at):
  // allocating gigabytes per input would only slow the fuzzer down.
  const std::size_t pixels = std::size_t{width} * height;
  std::vector<uint8_t> raw_depth(depth_payload || pixels > (1u << 20) ? 0 : pixels * 2, 0);
  std::vector<uint8_t>& depth = depth_payload ? payload : raw_depth;
  msg.depth = {static_cast<uint32_t>(depth.size()), static_cast<uint32_t>(depth.size()),
               depth.empty() ? nullptr : depth.data(), false};
  if (!depth_payload) {
    msg.color = {static_cast<uint32_t>(payload.size()), static_cast<uint32_t>(payload.size()),
                 payload.empty() ? nullptr : payload.data(), false};
  }
  if (kind == 3 && pixels <= (1u << 20)) {
    auto units = semfuse::wire::decodeRvl(payload.data(), payload.size(),
                                          cv::Size(static_cast<int>(width), static_cast<int>(height)));
    if (units) SEMFUSE_FUZZ_CHECK(semfuse::wire::encodeRvl(units.value()).value() == payload);
  }
  auto frame = semfuse::wire::decodeFrame(msg);
  if (!frame) return 0;
  SEMFUSE_FUZZ_CHECK(frame.value().depth.cols == static_cast<int>(width));
  SEMFUSE_FUZZ_CHECK(frame.value().depth.rows == static_cast<int>(height));
  if (!depth_payload) SEMFUSE_FUZZ_CHECK(frame.value().color.size() == frame.value().depth.size());
  return 0;
}
