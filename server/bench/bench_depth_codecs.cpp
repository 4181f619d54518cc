// semfuse-bench depth-codecs: what each depth encoding of a Frame costs: bytes on the wire, the
// camera's encode and the server's decode (wire::decodeFrame, what the ingest thread runs for
// every frame: checks, decompression, units to metres), per frame of the shared 7-Scenes and TUM
// sequences. Colour is left out (encoding ""), so the figures are the depth's alone. Each
// compressed encoding also shows its decompression alone (the RVL decoder, OpenCV's PNG decoder),
// and every decoded image is checked against the raw one: the compressed encodings are lossless.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/datasets/tum_rgbd.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/rvl_codec.hpp"

namespace semfuse::bench {
namespace {

struct DepthCodecOptions {
  std::string seven_scenes = redkitchenDir().string();
  std::string tum = (sharedDir() / "data" / "rgbd_dataset_freiburg1_xyz").string();
  std::size_t frames = 100;  // per sequence, spread evenly over it
  int repeats = 5;           // decodes of each frame per encoding
  double depth_scale = 0.001;
  std::vector<std::string> encodings{"raw", "png", "rvl"};
};

struct CodecSequence {
  std::string name;
  std::vector<Frame> frames;  // depth only
};

template <class Reader>
Result<CodecSequence> loadCodecSequence(const std::string& name, const Reader& reader, std::size_t wanted) {
  CodecSequence sequence{name, {}};
  const std::size_t count = reader.count();
  const std::size_t n = std::min(wanted, count);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t index = k * count / n;
    auto frame = reader.loadDepthOnly(index);
    if (!frame) return makeError(name + " frame " + std::to_string(index) + ": " + frame.error());
    sequence.frames.push_back(std::move(frame).value());
  }
  if (sequence.frames.empty()) return makeError(name + ": no frames");
  return sequence;
}

std::string wireName(const std::string& encoding) {
  return encoding == "raw" ? "16UC1" : encoding == "png" ? "png16" : encoding;
}

// The decompression alone: the 16-bit image from the payload, without the frame's checks and the
// conversion to metres.
cv::Mat decompress(const std::string& encoding, const semfuse_msg_dds__Frame_& msg) {
  const cv::Size size(static_cast<int>(msg.intrinsics.width), static_cast<int>(msg.intrinsics.height));
  if (encoding == "rvl") {
    auto units = wire::decodeRvl(msg.depth._buffer, msg.depth._length, size);
    return units ? units.value() : cv::Mat();
  }
  const cv::Mat payload(1, static_cast<int>(msg.depth._length), CV_8UC1, msg.depth._buffer);
  return cv::imdecode(payload, cv::IMREAD_ANYDEPTH);
}

struct EncodingResult {
  std::string encoding;
  double bytes = 0;  // mean per frame
  Timings encode, decode, decompress;
  std::size_t mismatched_pixels = 0;  // against the raw encoding's decode
};

Result<EncodingResult> measureEncoding(const CodecSequence& sequence, const std::string& encoding,
                                       const DepthCodecOptions& o, const std::vector<cv::Mat>& reference) {
  EncodingResult result;
  result.encoding = encoding;
  wire::FrameEncoding wire_encoding;
  wire_encoding.depth = wireName(encoding);
  wire_encoding.depth_scale = o.depth_scale;
  wire_encoding.color = "";
  std::vector<wire::EncodedFrame> encoded;
  for (const Frame& frame : sequence.frames) {
    Stopwatch watch;
    auto message = wire::encodeFrame(frame, wire_encoding);
    result.encode.add(watch.elapsedMs());
    if (!message) return makeError(encoding + ": " + message.error());
    result.bytes += message.value().msg().depth._length;
    encoded.push_back(std::move(message).value());
  }
  result.bytes /= static_cast<double>(encoded.size());
  for (int r = 0; r < o.repeats; ++r) {
    for (std::size_t i = 0; i < encoded.size(); ++i) {
      Stopwatch watch;
      auto decoded = wire::decodeFrame(encoded[i].msg());
      result.decode.add(watch.elapsedMs());
      if (!decoded) return makeError(encoding + ": frame " + std::to_string(i) + ": " + decoded.error());
      if (r == 0 && !reference.empty()) {
        result.mismatched_pixels += static_cast<std::size_t>(cv::countNonZero(decoded.value().depth != reference[i]));
      }
      if (encoding == "raw") continue;  // nothing to decompress
      Stopwatch alone;
      const cv::Mat units = decompress(encoding, encoded[i].msg());
      result.decompress.add(alone.elapsedMs());
      if (units.empty()) return makeError(encoding + ": frame " + std::to_string(i) + " does not decompress");
    }
  }
  return result;
}

int runCodecSequence(const CodecSequence& sequence, const DepthCodecOptions& o) {
  const cv::Size size = sequence.frames.front().depth.size();
  std::printf("\n%s: %zu frames %dx%d, depth_scale %g m, %d decodes of each frame per encoding\n",
              sequence.name.c_str(), sequence.frames.size(), size.width, size.height, o.depth_scale, o.repeats);
  // The raw encoding's decode is the reference the others must reproduce exactly.
  std::vector<cv::Mat> reference;
  {
    wire::FrameEncoding raw;
    raw.depth_scale = o.depth_scale;
    raw.color = "";
    for (const Frame& frame : sequence.frames) {
      auto message = wire::encodeFrame(frame, raw);
      auto decoded = message ? wire::decodeFrame(message.value().msg()) : Result<Frame>(message.errorInfo());
      if (!decoded) {
        std::fprintf(stderr, "semfuse-bench depth-codecs: %s\n", decoded.error().c_str());
        return 1;
      }
      reference.push_back(decoded.value().depth);
    }
  }
  std::vector<EncodingResult> results;
  for (const std::string& encoding : o.encodings) {
    auto result = measureEncoding(sequence, encoding, o, reference);
    if (!result) {
      std::fprintf(stderr, "semfuse-bench depth-codecs: %s\n", result.error().c_str());
      return 1;
    }
    results.push_back(std::move(result).value());
  }
  const double raw_bytes = static_cast<double>(size.area()) * 2.0;
  const auto png = std::find_if(results.begin(), results.end(), [](const auto& r) { return r.encoding == "png"; });
  std::printf("  %-8s %12s %9s %12s %22s %22s %10s %10s\n", "encoding", "kB/frame", "of raw", "encode ms",
              "decodeFrame ms p50/p95", "decompress ms p50/p95", "vs png", "lossless");
  for (const EncodingResult& r : results) {
    const std::string decompress = r.decompress.count() == 0 ? "-"
                                                             : formatNumber(r.decompress.median(), 3) + " / " +
                                                                   formatNumber(r.decompress.p95(), 3);
    const std::string ratio =
        png == results.end() ? "-" : formatNumber(png->decode.median() / r.decode.median(), 1) + "x";
    std::printf("  %-8s %12s %8s%% %12s %22s %22s %10s %10s\n", r.encoding.c_str(),
                formatNumber(r.bytes / 1000.0, 1).c_str(), formatNumber(100.0 * r.bytes / raw_bytes, 1).c_str(),
                formatNumber(r.encode.median(), 3).c_str(),
                (formatNumber(r.decode.median(), 3) + " / " + formatNumber(r.decode.p95(), 3)).c_str(),
                decompress.c_str(), ratio.c_str(), r.mismatched_pixels == 0 ? "yes" : "NO");
  }
  std::printf("  (vs png: png's decodeFrame median over this encoding's; load average %.2f)\n", loadAverage());
  for (const EncodingResult& r : results) {
    if (r.mismatched_pixels != 0) {
      std::fprintf(stderr, "semfuse-bench depth-codecs: %s: %zu pixels differ from the raw encoding's\n",
                   r.encoding.c_str(), r.mismatched_pixels);
      return 1;
    }
  }
  return 0;
}

int runDepthCodecs(const DepthCodecOptions& o) {
  for (const std::string& encoding : o.encodings) {
    if (encoding != "raw" && encoding != "png" && encoding != "rvl") {
      std::fprintf(stderr, "semfuse-bench depth-codecs: unknown encoding '%s' (raw, png, rvl)\n", encoding.c_str());
      return 2;
    }
  }
  std::vector<CodecSequence> sequences;
  if (!o.seven_scenes.empty()) {
    auto reader = datasets::SevenScenesReader::open(o.seven_scenes);
    auto sequence = reader ? loadCodecSequence("7-Scenes " + std::filesystem::path(o.seven_scenes).filename().string(),
                                               reader.value(), o.frames)
                           : Result<CodecSequence>(reader.errorInfo());
    if (!sequence) {
      std::fprintf(stderr, "semfuse-bench depth-codecs: %s\n", sequence.error().c_str());
      return 1;
    }
    sequences.push_back(std::move(sequence).value());
  }
  if (!o.tum.empty()) {
    auto reader = datasets::TumRgbdReader::open(o.tum);
    auto sequence =
        reader ? loadCodecSequence("TUM " + std::filesystem::path(o.tum).filename().string(), reader.value(), o.frames)
               : Result<CodecSequence>(reader.errorInfo());
    if (!sequence) {
      std::fprintf(stderr, "semfuse-bench depth-codecs: %s\n", sequence.error().c_str());
      return 1;
    }
    sequences.push_back(std::move(sequence).value());
  }
  int code = 0;
  for (const CodecSequence& sequence : sequences) code = std::max(code, runCodecSequence(sequence, o));
  return code;
}

const bool depth_codecs_registered = registerBench(
    "depth-codecs", "bytes, encode and decode time of each depth encoding (raw, png, rvl) on 7-Scenes and TUM frames",
    [](CLI::App& command) {
      auto options = std::make_shared<DepthCodecOptions>();
      command.add_option("--seven-scenes", options->seven_scenes, "7-Scenes sequence folder (\"\" = skip)")
          ->capture_default_str();
      command.add_option("--tum", options->tum, "TUM RGB-D sequence folder (\"\" = skip)")->capture_default_str();
      command.add_option("--frames", options->frames, "frames per sequence, spread over it")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
      command.add_option("--repeats", options->repeats, "decodes of each frame per encoding")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
      command.add_option("--depth-scale", options->depth_scale, "metres per unit of the 16-bit encodings")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
      command.add_option("--encodings", options->encodings, "encodings to measure: raw, png, rvl")
          ->delimiter(',')
          ->capture_default_str();
      return [options] { return runDepthCodecs(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
