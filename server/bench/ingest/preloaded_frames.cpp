#include "preloaded_frames.hpp"

#include <algorithm>
#include <string>

#include "interrupt.hpp"
#include "semfuse/datasets/seven_scenes.hpp"

namespace semfuse::bench::ingest {

std::string depthWireEncoding(const std::string& option) {
  return option == "png" ? "png16" : option == "rvl" ? "rvl" : "16UC1";
}

Result<Preloaded> preload(const IngestOptions& options) {
  auto reader = datasets::SevenScenesReader::open(options.data);
  if (!reader) return makeError("7-Scenes: " + reader.error());
  const auto& r = reader.value();
  wire::FrameEncoding encoding;
  encoding.depth = depthWireEncoding(options.depth);
  encoding.color = "jpeg";
  Preloaded out;
  out.intrinsics = r.intrinsics();
  const std::size_t count = std::min(options.frames, r.count());
  for (std::size_t i = 0; i < count && !interrupted(); ++i) {
    auto frame = r.load(i);
    if (!frame) return makeError("frame " + std::to_string(i) + ": " + frame.error());
    if (!frame.value().camera_to_world) return makeError("frame " + std::to_string(i) + " has no pose");
    auto encoded = wire::encodeFrame(frame.value(), encoding);
    if (!encoded) return makeError("encode frame " + std::to_string(i) + ": " + encoded.error());
    out.depth_kb += encoded.value().msg().depth._length / 1024.0;
    out.color_kb += encoded.value().msg().color._length / 1024.0;
    out.poses.push_back(*frame.value().camera_to_world);
    out.frames.push_back(std::move(encoded).value());
  }
  if (out.frames.empty()) return makeError("no frames loaded");
  out.depth_kb /= static_cast<double>(out.frames.size());
  out.color_kb /= static_cast<double>(out.frames.size());
  return out;
}

}  // namespace semfuse::bench::ingest
