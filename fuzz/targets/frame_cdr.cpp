// Fuzz target: a serialized semfuse::msg::dds_::Frame_ (CDR, header included) as the server's
// frame reader receives it -> CDR validation and decoding -> wire::decodeFrame (sizes,
// intrinsics, encodings, raw / PNG / JPEG payloads, pose). Anything malformed must come back as
// an error; what decodes must be what types.hpp promises.
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "fuzz_support.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/frame_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto sample = semfuse::dds::deserialize<semfuse_msg_dds__Frame_>(data, size);
  if (!sample) return 0;
  auto frame = semfuse::wire::decodeFrame(*sample.value());
  if (!frame) return 0;
  const semfuse::Frame& f = frame.value();
  SEMFUSE_FUZZ_CHECK(f.depth.type() == CV_32FC1);
  SEMFUSE_FUZZ_CHECK(f.depth.cols == static_cast<int>(sample.value()->intrinsics.width));
  SEMFUSE_FUZZ_CHECK(f.depth.rows == static_cast<int>(sample.value()->intrinsics.height));
  SEMFUSE_FUZZ_CHECK(f.color.empty() || (f.color.type() == CV_8UC3 && f.color.size() == f.depth.size()));
  SEMFUSE_FUZZ_CHECK(!f.camera_id.empty());
  return 0;
}
