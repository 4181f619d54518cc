// ROS 2 compressed depth images (compressed_depth_image_transport's format) <-> metres.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include <opencv2/imgcodecs.hpp>

#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/image_convert.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "semfuse/wire/rvl_codec.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::wire {
namespace {

enum class DepthCompression { kPng, kRvl };

struct DepthFormat {
  std::string encoding;  // lower case: 16uc1, mono16 or 32fc1
  DepthCompression compression = DepthCompression::kPng;
  bool config_header = true;  // false for compressed_image_transport's plain PNG
};

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(' ');
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(' ') - first + 1);
}

// "16UC1; compressedDepth rvl" -> 16uc1, RVL. The compression after "compressedDepth" is read as
// compressed_depth_image_transport reads it: none given is PNG.
Result<DepthFormat> parseDepthFormat(const std::string& raw_format) {
  const std::string format = lowerCase(raw_format);
  const auto split = format.find(';');
  DepthFormat parsed;
  parsed.encoding = trimmed(format.substr(0, split));
  if (parsed.encoding != "16uc1" && parsed.encoding != "mono16" && parsed.encoding != "32fc1") {
    return makeError("compressed depth: format '" + raw_format + "' is not of a depth encoding (16UC1, mono16, 32FC1)");
  }
  const std::string rest = split == std::string::npos ? std::string() : format.substr(split + 1);
  const std::string marker = "compresseddepth";
  const auto at = rest.find(marker);
  if (at == std::string::npos) {
    // compressed_image_transport's PNG of a 16-bit image, without the configuration header.
    if (rest.find("png") != std::string::npos && parsed.encoding != "32fc1") {
      parsed.config_header = false;
      return parsed;
    }
    return makeError("compressed depth: unknown format '" + raw_format +
                     "' (known: compressedDepth png or rvl, or a 16-bit png)");
  }
  const std::string compression = trimmed(rest.substr(at + marker.size()));
  if (compression.empty() || compression == "png") return parsed;
  if (compression == "rvl") {
    parsed.compression = DepthCompression::kRvl;
    return parsed;
  }
  return makeError("compressed depth: unknown compression '" + compression + "' in format '" + raw_format +
                   "' (known: png, rvl)");
}

uint32_t loadUint32(const uint8_t* p) {
  return uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
}
float loadFloat(const uint8_t* p) {
  const uint32_t bits = loadUint32(p);
  float value = 0.0f;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// The 16-bit image of a PNG payload, its declared size bounded and its chunks whole first.
Result<cv::Mat> decodeDepthPng(const uint8_t* data, std::size_t size) {
  auto declared = pngDeclaredSize(data, size);
  if (!declared) return makeError("compressed depth: PNG payload does not decode: " + declared.error());
  if (Status s = validateImageSize("compressed depth", declared.value().width, declared.value().height); !s) {
    return makeError(s.error());
  }
  if (Status whole = pngChunksComplete(data, size); !whole) {
    return makeError("compressed depth: PNG payload does not decode: " + whole.error());
  }
  const cv::Mat payload(1, static_cast<int>(size), CV_8UC1, const_cast<uint8_t*>(data));
  cv::Mat units;
  try {
    units = cv::imdecode(payload, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    units.release();  // reported below
  }
  if (Status s = validateDecodedImage("compressed depth", "PNG", units, static_cast<uint32_t>(declared.value().width),
                                      static_cast<uint32_t>(declared.value().height), CV_16UC1);
      !s) {
    return makeError(s.error());
  }
  return units;
}

Result<cv::Mat> decodeDepthRvl(const uint8_t* data, std::size_t size) {
  auto declared = rvlDeclaredSize(data, size);
  if (!declared) return makeError("compressed depth: " + declared.error());
  if (Status s = validateImageSize("compressed depth", declared.value().width, declared.value().height); !s) {
    return makeError(s.error());
  }
  auto units = decodeRvl(data, size, declared.value());
  if (!units) return makeError("compressed depth: " + units.error());
  return units;
}

// depth = a / (value - b) for the transport's quantised inverse depth; 0 stays "no depth".
Result<cv::Mat> inverseDepthToMetres(const cv::Mat& quantised, float a, float b) {
  if (!std::isfinite(a) || !std::isfinite(b) || !(a > 0.0f)) {
    return makeError("compressed depth: inverse depth parameters a " + std::to_string(a) + ", b " + std::to_string(b) +
                     " (a must be finite and > 0, b finite)");
  }
  cv::Mat metres(quantised.size(), CV_32FC1);
  for (int y = 0; y < quantised.rows; ++y) {
    const uint16_t* in = quantised.ptr<uint16_t>(y);
    float* out = metres.ptr<float>(y);
    for (int x = 0; x < quantised.cols; ++x) {
      if (in[x] == 0) {
        out[x] = 0.0f;
        continue;
      }
      const float depth = a / (static_cast<float>(in[x]) - b);
      if (!std::isfinite(depth) || !(depth > 0.0f)) {
        return makeError("compressed depth: value " + std::to_string(in[x]) + " at (" + std::to_string(x) + ", " +
                         std::to_string(y) + ") decodes to depth " + std::to_string(depth) + " with a " +
                         std::to_string(a) + ", b " + std::to_string(b));
      }
      out[x] = depth;
    }
  }
  return metres;
}

}  // namespace

Result<cv::Mat> compressedDepthToMetres(const sensor_msgs_msg_dds__CompressedImage_& msg) {
  auto format = parseDepthFormat(stringOf(msg.format));
  if (!format) return format.errorInfo();
  if (Status s = validateSequence("compressed depth", msg.data._length, msg.data._maximum, msg.data._buffer); !s) {
    return makeError(s.error());
  }
  const uint8_t* data = msg.data._buffer;
  std::size_t size = msg.data._length;
  if (!format.value().config_header) {
    auto units = decodeDepthPng(data, size);
    if (!units) return units;
    return depthUnitsToMetres(units.value(), 0.001);
  }
  if (size <= kCompressedDepthHeaderBytes) {
    return makeError("compressed depth: " + std::to_string(size) + " bytes, no payload after the " +
                     std::to_string(kCompressedDepthHeaderBytes) + "-byte configuration header");
  }
  const uint32_t kind = loadUint32(data);
  if (kind != 0) {
    return makeError("compressed depth: configuration header says compression format " + std::to_string(kind) +
                     " (known: 0, inverse depth)");
  }
  const float a = loadFloat(data + 4), b = loadFloat(data + 8);
  data += kCompressedDepthHeaderBytes;
  size -= kCompressedDepthHeaderBytes;
  auto units =
      format.value().compression == DepthCompression::kRvl ? decodeDepthRvl(data, size) : decodeDepthPng(data, size);
  if (!units) return units;
  if (format.value().encoding == "32fc1") return inverseDepthToMetres(units.value(), a, b);
  return depthUnitsToMetres(units.value(), 0.001);
}

Result<OwnedMessage<sensor_msgs_msg_dds__CompressedImage_>> compressedDepthFromMillimetres(
    const cv::Mat& millimetres, const std::string& compression, Stamp stamp, const std::string& frame_id) {
  if (millimetres.type() != CV_16UC1) {
    return makeError("compressed depth: millimetres must be CV_16UC1, got " + typeName(millimetres.type()));
  }
  if (Status s = validateImageSize("compressed depth", millimetres.cols, millimetres.rows); !s) {
    return makeError(s.error());
  }
  std::vector<uint8_t> payload;
  if (compression == "rvl") {
    auto rvl = encodeRvl(millimetres);
    if (!rvl) return rvl.errorInfo();
    payload = std::move(rvl).value();
  } else if (compression == "png") {
    if (!cv::imencode(".png", millimetres, payload)) return makeError("compressed depth: the PNG encoder failed");
  } else {
    return makeError("compressed depth: unknown compression '" + compression + "' (known: png, rvl)");
  }
  // Configuration header all zero: format 0 (inverse depth, which the transport writes for 16UC1
  // too) and the quantisation parameters, unused for millimetres.
  std::vector<uint8_t> data(kCompressedDepthHeaderBytes + payload.size(), 0);
  std::copy(payload.begin(), payload.end(), data.begin() + kCompressedDepthHeaderBytes);
  OwnedMessage<sensor_msgs_msg_dds__CompressedImage_> owned;
  fillHeader(owned, owned.msg().header, stamp, frame_id);
  owned.msg().format = owned.keepString("16UC1; compressedDepth " + compression);
  owned.keepSequence(owned.msg().data, std::move(data));
  return owned;
}

}  // namespace semfuse::wire
