#include "semfuse/wire/rvl_codec.hpp"

#include <algorithm>
#include <limits>
#include <string>

namespace semfuse::wire {
namespace {

// Largest zigzag-coded difference of two 16-bit values (|d| <= 65535).
constexpr uint32_t kMaxRvlDelta = 2u * 65535u;
// A count or value takes at most 11 nibbles (33 bits) before the decoder gives up on it.
constexpr int kMaxVleNibbles = 11;

uint32_t loadLittleEndian32(const uint8_t* p) {
  return uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
}

void appendLittleEndian32(std::vector<uint8_t>& out, uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<uint8_t>(value >> shift));
}

class NibbleWriter {
 public:
  explicit NibbleWriter(std::vector<uint8_t>& out) : out_(out) {}
  void put(uint32_t nibble) {
    word_ = (word_ << 4) | nibble;
    if (++count_ == 8) store();
  }
  // Fills the last word with zero nibbles, as the decoder expects.
  void finish() {
    if (count_ == 0) return;
    word_ <<= 4 * (8 - count_);
    store();
  }
  // 3 bits a nibble, least significant first, the top bit set when more follow.
  void putVariable(uint32_t value) {
    do {
      uint32_t nibble = value & 7u;
      value >>= 3;
      if (value != 0) nibble |= 8u;
      put(nibble);
    } while (value != 0);
  }

 private:
  void store() {
    appendLittleEndian32(out_, word_);
    word_ = 0;
    count_ = 0;
  }
  std::vector<uint8_t>& out_;
  uint32_t word_ = 0;
  int count_ = 0;
};

enum class VleRead { kOk, kTruncated, kTooLong, kSuperfluousNibble };

class NibbleReader {
 public:
  NibbleReader(const uint8_t* begin, const uint8_t* end) : next_(begin), end_(end) {}

  VleRead readVariable(uint32_t& value) {
    uint32_t nibble = 0;
    if (!take(nibble)) return VleRead::kTruncated;
    if ((nibble & 8u) == 0) {  // the common case: a small delta in one nibble
      value = nibble;
      return VleRead::kOk;
    }
    uint64_t bits = nibble & 7u;
    for (int shift = 3;; shift += 3) {
      if (shift >= 3 * kMaxVleNibbles) return VleRead::kTooLong;
      if (!take(nibble)) return VleRead::kTruncated;
      bits |= uint64_t{nibble & 7u} << shift;
      if ((nibble & 8u) == 0) {
        // A last nibble of 0 adds nothing: the encoder would have stopped before it.
        if (nibble == 0) return VleRead::kSuperfluousNibble;
        break;
      }
    }
    if (bits > std::numeric_limits<uint32_t>::max()) return VleRead::kTooLong;
    value = static_cast<uint32_t>(bits);
    return VleRead::kOk;
  }

  // After the last pixel: the rest of the current word must be zero and no word may follow.
  Status checkEnd() const {
    if (count_ > 0 && word_ != 0) return makeError("RVL payload has non-zero padding after the last pixel");
    if (next_ != end_) {
      return makeError("RVL payload has " + std::to_string(end_ - next_) + " bytes after the last pixel");
    }
    return Status::Ok();
  }

 private:
  bool take(uint32_t& nibble) {
    if (count_ == 0) {
      if (next_ == end_) return false;
      word_ = loadLittleEndian32(next_);
      next_ += 4;
      count_ = 8;
    }
    nibble = word_ >> 28;
    word_ <<= 4;
    --count_;
    return true;
  }

  const uint8_t* next_;
  const uint8_t* end_;
  uint32_t word_ = 0;
  int count_ = 0;
};

std::string readError(VleRead result, std::size_t pixel, std::size_t pixels) {
  switch (result) {
    case VleRead::kTruncated:
      return "RVL payload ends at pixel " + std::to_string(pixel) + " of " + std::to_string(pixels) + " (truncated)";
    case VleRead::kTooLong:
      return "RVL payload has a count or value longer than 32 bits at pixel " + std::to_string(pixel);
    case VleRead::kSuperfluousNibble:
      return "RVL payload has a count or value with a superfluous zero nibble at pixel " + std::to_string(pixel);
    case VleRead::kOk:
      break;
  }
  return {};
}

std::string overflowError(const char* kind, uint32_t run, std::size_t pixel, std::size_t pixels) {
  return "RVL payload has a run of " + std::to_string(run) + " " + kind + " pixels at pixel " + std::to_string(pixel) +
         " that overflows the " + std::to_string(pixels) + "-pixel image";
}

// The stream after the size header into `out` (`pixels` values).
Status decodeStream(NibbleReader& reader, uint16_t* out, std::size_t pixels) {
  std::size_t pixel = 0;
  int32_t previous = 0;
  for (bool first = true;; first = false) {
    uint32_t zeros = 0;
    if (VleRead r = reader.readVariable(zeros); r != VleRead::kOk) return makeError(readError(r, pixel, pixels));
    // Only the first pair may start on a non-zero pixel: a later one follows a non-zero run that
    // stopped at a zero.
    if (zeros == 0 && !first)
      return makeError("RVL payload has an empty run of zeros at pixel " + std::to_string(pixel));
    if (zeros > pixels - pixel) return makeError(overflowError("zero", zeros, pixel, pixels));
    std::fill_n(out + pixel, zeros, uint16_t{0});
    pixel += zeros;

    uint32_t nonzeros = 0;
    if (VleRead r = reader.readVariable(nonzeros); r != VleRead::kOk) return makeError(readError(r, pixel, pixels));
    if (nonzeros > pixels - pixel) return makeError(overflowError("non-zero", nonzeros, pixel, pixels));
    if (nonzeros == 0 && pixel != pixels) {
      return makeError("RVL payload has an empty run of non-zero pixels at pixel " + std::to_string(pixel));
    }
    for (const std::size_t run_end = pixel + nonzeros; pixel < run_end; ++pixel) {
      uint32_t zigzag = 0;
      if (VleRead r = reader.readVariable(zigzag); r != VleRead::kOk) return makeError(readError(r, pixel, pixels));
      if (zigzag > kMaxRvlDelta) {
        return makeError("RVL payload has a difference of " + std::to_string(zigzag) + " (zigzag) at pixel " +
                         std::to_string(pixel) + ", beyond any two 16-bit values");
      }
      const int32_t delta = (zigzag & 1u) ? -static_cast<int32_t>((zigzag + 1) / 2) : static_cast<int32_t>(zigzag / 2);
      const int32_t value = previous + delta;
      if (value < 1 || value > 65535) {
        return makeError("RVL payload decodes pixel " + std::to_string(pixel) + " of a non-zero run to " +
                         std::to_string(value) + ", outside 1..65535");
      }
      out[pixel] = static_cast<uint16_t>(value);
      previous = value;
    }
    if (pixel == pixels) return reader.checkEnd();
  }
}

}  // namespace

Result<std::vector<uint8_t>> encodeRvl(const cv::Mat& units) {
  if (units.type() != CV_16UC1) return makeError("RVL encodes CV_16UC1 images only");
  if (units.empty()) return makeError("RVL: empty image");
  const cv::Mat continuous = units.isContinuous() ? units : units.clone();
  const auto* p = continuous.ptr<uint16_t>();
  const auto* const end = p + continuous.total();

  std::vector<uint8_t> out;
  out.reserve(kRvlHeaderBytes + continuous.total());  // depth images take 1-2 nibbles a pixel
  appendLittleEndian32(out, static_cast<uint32_t>(continuous.cols));
  appendLittleEndian32(out, static_cast<uint32_t>(continuous.rows));
  NibbleWriter writer(out);
  int32_t previous = 0;
  while (p != end) {
    const auto* const zeros = p;
    while (p != end && *p == 0) ++p;
    writer.putVariable(static_cast<uint32_t>(p - zeros));
    const auto* const nonzeros = p;
    while (p != end && *p != 0) ++p;
    writer.putVariable(static_cast<uint32_t>(p - nonzeros));
    for (const auto* q = nonzeros; q != p; ++q) {
      const int32_t delta = static_cast<int32_t>(*q) - previous;
      writer.putVariable(delta >= 0 ? 2u * static_cast<uint32_t>(delta) : 2u * static_cast<uint32_t>(-delta) - 1u);
      previous = *q;
    }
  }
  writer.finish();
  return out;
}

Result<cv::Size> rvlDeclaredSize(const uint8_t* data, std::size_t size) {
  if (data == nullptr || size < kRvlHeaderBytes) {
    return makeError("RVL payload of " + std::to_string(size) + " bytes is shorter than its " +
                     std::to_string(kRvlHeaderBytes) + "-byte size header");
  }
  const uint32_t width = loadLittleEndian32(data), height = loadLittleEndian32(data + 4);
  constexpr auto kIntMax = static_cast<uint32_t>(std::numeric_limits<int>::max());
  if (width > kIntMax || height > kIntMax) {
    return makeError("RVL payload declares " + std::to_string(width) + "x" + std::to_string(height) + " pixels");
  }
  return cv::Size(static_cast<int>(width), static_cast<int>(height));
}

Result<cv::Mat> decodeRvl(const uint8_t* data, std::size_t size, cv::Size expected) {
  auto declared = rvlDeclaredSize(data, size);
  if (!declared) return makeError(declared.error());
  if (declared.value() != expected) {
    return makeError("RVL payload declares " + std::to_string(declared.value().width) + "x" +
                     std::to_string(declared.value().height) + ", expected " + std::to_string(expected.width) + "x" +
                     std::to_string(expected.height));
  }
  if (expected.width <= 0 || expected.height <= 0) return makeError("RVL payload declares an empty image");
  const std::size_t stream = size - kRvlHeaderBytes;
  if (stream % 4 != 0) {
    return makeError("RVL payload's stream of " + std::to_string(stream) + " bytes is not whole 32-bit words");
  }
  cv::Mat units(expected, CV_16UC1);
  NibbleReader reader(data + kRvlHeaderBytes, data + size);
  if (Status s = decodeStream(reader, units.ptr<uint16_t>(), units.total()); !s) return s.errorInfo();
  return units;
}

}  // namespace semfuse::wire
