#include "semfuse/wire/validation.hpp"

#include <algorithm>
#include <array>
#include <sstream>

#include <opencv2/core.hpp>

#include "semfuse/core/number_text.hpp"

namespace semfuse::wire {

namespace {

constexpr std::array<uint8_t, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
bool hasPngSignature(const uint8_t* data, std::size_t size) {
  return size >= kPngSignature.size() && std::equal(kPngSignature.begin(), kPngSignature.end(), data);
}

std::string size(int64_t width, int64_t height) { return std::to_string(width) + "x" + std::to_string(height); }

}  // namespace

std::string typeName(int cv_type) {
  std::string name = cv::typeToString(cv_type);
  return name.rfind("CV_", 0) == 0 ? name.substr(3) : name;
}

Status validateImageSize(const std::string& what, int64_t width, int64_t height, uint32_t max_side) {
  if (width <= 0 || height <= 0) return makeError(what + ": image size " + size(width, height) + " is empty");
  if (width > max_side || height > max_side) {
    return makeError(what + ": image size " + size(width, height) + " exceeds the " + std::to_string(max_side) +
                     "-pixel limit");
  }
  return Status::Ok();
}

Status validateSequence(const std::string& what, uint32_t length, uint32_t maximum, const void* buffer) {
  if (length > maximum) {
    return makeError(what + ": truncated sequence, length " + std::to_string(length) + " exceeds its allocation of " +
                     std::to_string(maximum));
  }
  if (length > 0 && buffer == nullptr) {
    return makeError(what + ": truncated sequence, length " + std::to_string(length) + " but no data");
  }
  return Status::Ok();
}

Status validateDataSize(const std::string& what, std::size_t bytes, uint32_t width, uint32_t height,
                        const std::string& encoding, std::size_t bytes_per_pixel) {
  const uint64_t expected = static_cast<uint64_t>(width) * height * bytes_per_pixel;
  if (bytes != expected) {
    return makeError(what + ": " + std::to_string(bytes) + " bytes for " + size(width, height) + " " + encoding +
                     ", expected " + std::to_string(expected));
  }
  return Status::Ok();
}

Status validateEncoding(const std::string& what, const std::string& encoding, const std::vector<std::string>& known) {
  for (const std::string& name : known) {
    if (name == encoding) return Status::Ok();
  }
  std::string list;
  for (const std::string& name : known) list += (list.empty() ? "" : ", ") + (name.empty() ? "\"\"" : name);
  return makeError(what + ": unknown encoding '" + encoding + "' (known: " + list + ")");
}

Status validateDecodedImage(const std::string& what, const std::string& format, const cv::Mat& decoded, uint32_t width,
                            uint32_t height, int expected_type) {
  if (decoded.empty()) return makeError(what + ": " + format + " payload does not decode");
  if (decoded.cols != static_cast<int>(width) || decoded.rows != static_cast<int>(height) ||
      decoded.type() != expected_type) {
    return makeError(what + ": " + format + " decodes to " + size(decoded.cols, decoded.rows) + " " +
                     typeName(decoded.type()) + ", declared " + size(width, height) + " " + typeName(expected_type));
  }
  return Status::Ok();
}

Result<cv::Size> pngDeclaredSize(const uint8_t* data, std::size_t size) {
  // 8-byte signature, then the IHDR chunk: length (4), "IHDR" (4), width (4, big-endian), height (4).
  if (data == nullptr || size < 24 || !hasPngSignature(data, size) ||
      std::string(reinterpret_cast<const char*>(data) + 12, 4) != "IHDR") {
    return makeError("not a PNG (bad signature or header)");
  }
  const auto be32 = [&](std::size_t at) {
    return (uint32_t{data[at]} << 24) | (uint32_t{data[at + 1]} << 16) | (uint32_t{data[at + 2]} << 8) | data[at + 3];
  };
  const uint32_t width = be32(16), height = be32(20);
  if (width > static_cast<uint32_t>(INT32_MAX) || height > static_cast<uint32_t>(INT32_MAX)) {
    return makeError("PNG declares an impossible size " + std::to_string(width) + "x" + std::to_string(height));
  }
  return cv::Size(static_cast<int>(width), static_cast<int>(height));
}

Status pngChunksComplete(const uint8_t* data, std::size_t size) {
  constexpr std::size_t kChunkOverhead = 12;  // length (4), type (4), CRC (4) around the data
  if (data == nullptr || !hasPngSignature(data, size)) return makeError("not a PNG (bad signature or header)");
  std::size_t at = kPngSignature.size();
  while (size - at >= kChunkOverhead) {
    const uint64_t length =
        (uint64_t{data[at]} << 24) | (uint64_t{data[at + 1]} << 16) | (uint64_t{data[at + 2]} << 8) | data[at + 3];
    const std::string type(reinterpret_cast<const char*>(data) + at + 4, 4);
    if (length > size - at - kChunkOverhead) {
      return makeError("truncated: chunk '" + type + "' at byte " + std::to_string(at) + " declares " +
                       std::to_string(length) + " bytes, " + std::to_string(size - at - kChunkOverhead) + " left");
    }
    if (type == "IEND") return Status::Ok();
    at += kChunkOverhead + static_cast<std::size_t>(length);
  }
  return makeError("truncated: no IEND chunk in " + std::to_string(size) + " bytes");
}

Result<cv::Size> jpegDeclaredSize(const uint8_t* data, std::size_t size) {
  if (data == nullptr || size < 4 || data[0] != 0xFF || data[1] != 0xD8) return makeError("not a JPEG (no SOI marker)");
  const auto be16 = [&](std::size_t at) { return static_cast<uint32_t>((data[at] << 8) | data[at + 1]); };
  std::size_t at = 2;
  while (at + 4 <= size) {
    if (data[at] != 0xFF) return makeError("not a JPEG (bytes between segments at offset " + std::to_string(at) + ")");
    const uint8_t marker = data[at + 1];
    if (marker == 0xFF) {  // fill byte before a marker
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // TEM, RSTn: no length
      at += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) return makeError("JPEG has no frame header before its scan data");
    // SOF0..SOF15 except DHT (C4), JPG (C8) and DAC (CC): precision (1), height (2), width (2).
    const bool frame_header = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame_header) {
      if (at + 9 > size) break;
      return cv::Size(static_cast<int>(be16(at + 7)), static_cast<int>(be16(at + 5)));
    }
    const uint32_t length = be16(at + 2);  // includes its own two bytes
    if (length < 2) return makeError("JPEG segment with length " + std::to_string(length));
    at += 2 + length;
  }
  return makeError("JPEG ends before its frame header");
}

Status validateSegmentationSize(uint32_t seg_width, uint32_t seg_height, uint32_t frame_width, uint32_t frame_height) {
  if (seg_width > frame_width || seg_height > frame_height) {
    return makeError("segmentation: " + size(seg_width, seg_height) + " is larger than its frame " +
                     size(frame_width, frame_height));
  }
  return Status::Ok();
}

Status validateConfidence(const cv::Mat& confidence) {
  if (confidence.type() != CV_32FC1) {
    return makeError("confidence: type " + typeName(confidence.type()) + ", expected 32FC1");
  }
  for (int y = 0; y < confidence.rows; ++y) {
    const float* row = confidence.ptr<float>(y);
    for (int x = 0; x < confidence.cols; ++x) {
      if (!(row[x] >= 0.0f && row[x] <= 1.0f)) {  // also catches NaN
        return makeError("confidence: value " + numberText(row[x]) + " at (" + std::to_string(x) + ", " +
                         std::to_string(y) + ") outside [0, 1]");
      }
    }
  }
  return Status::Ok();
}

Status validateLabels(const cv::Mat& labels, const LabelLegend& legend) {
  if (labels.type() != CV_16UC1) return makeError("labels: type " + typeName(labels.type()) + ", expected 16UC1");
  // A lookup table over all 65536 ids keeps this one pass without a search per pixel.
  std::vector<bool> known(65536, false);
  for (const LabelInfo& info : legend.labels) known[info.id] = true;
  uint64_t bad = 0;
  int first_x = -1, first_y = -1;
  LabelId first_id = 0;
  for (int y = 0; y < labels.rows; ++y) {
    const uint16_t* row = labels.ptr<uint16_t>(y);
    for (int x = 0; x < labels.cols; ++x) {
      if (known[row[x]]) continue;
      if (bad++ == 0) {
        first_x = x;
        first_y = y;
        first_id = row[x];
      }
    }
  }
  if (bad == 0) return Status::Ok();
  return makeError("labels: " + std::to_string(bad) + " pixel" + (bad == 1 ? "" : "s") + " with ids outside legend '" +
                   legend.name + "' (max id " + std::to_string(legend.maxId()) + "); first: id " +
                   std::to_string(first_id) + " at (" + std::to_string(first_x) + ", " + std::to_string(first_y) + ")");
}

}  // namespace semfuse::wire
