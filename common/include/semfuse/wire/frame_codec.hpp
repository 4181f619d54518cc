#pragma once
// Frame <-> semfuse::msg::dds_::Frame_. Encodings (the strings on the wire):
//   depth:  "16UC1" raw units (depth_scale metres per unit), "32FC1" raw metres,
//           "png16" 16-bit PNG of units, "rvl" RVL-compressed units (rvl_codec.hpp), both
//           depth_scale metres per unit
//   colour: "" none, "rgb8" / "bgr8" raw, "jpeg", "png"
#include <string>
#include <vector>

#include <msg.h>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/wire/owned_message.hpp"

namespace semfuse::wire {

using EncodedFrame = OwnedMessage<semfuse_msg_dds__Frame_>;

const std::vector<std::string>& depthEncodings();  // 16UC1, 32FC1, png16, rvl
const std::vector<std::string>& colorEncodings();  // "", rgb8, bgr8, jpeg, png

struct FrameEncoding {
  std::string depth = "16UC1";
  double depth_scale = 0.001;  // metres per unit for 16UC1, png16 and rvl
  std::string color = "rgb8";  // "" sends no colour; a frame without colour is sent as ""
  int jpeg_quality = 90;       // 0-100
  int png_compression = 1;     // 0-9: fast by default, depth PNGs gain little from more
};

// Fails on a frame that is not what types.hpp promises (depth CV_32FC1, colour CV_8UC3 of the
// same size or empty), on unknown encodings or on an encoder failure.
Result<EncodedFrame> encodeFrame(const Frame& frame, const FrameEncoding& encoding = {});

// Validates everything (sizes, intrinsics, encodings, payloads, pose) and decodes to a Frame.
Result<Frame> decodeFrame(const semfuse_msg_dds__Frame_& msg);

// Row-major 3x4 [R|t] <-> Pose (shared by every message that carries a pose).
void poseToRowMajor(const Pose& pose, double out[12]);
Pose poseFromRowMajor(const double in[12]);

// A C string field that may be null (a default-constructed message) as std::string.
inline std::string stringOf(const char* text) { return text ? std::string(text) : std::string(); }

}  // namespace semfuse::wire
