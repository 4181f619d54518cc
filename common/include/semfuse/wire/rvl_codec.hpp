#pragma once
// RVL, lossless compression of 16-bit depth images (Wilson, "Fast Lossless Depth Image
// Compression", ISS 2017): runs of zero pixels and the deltas between consecutive non-zero ones,
// in variable-length 4-bit nibbles. Several times faster to decode than PNG and usually smaller.
//
// The payload (the "rvl" depth encoding of a Frame, and what follows the 12-byte configuration
// header of a ROS compressedDepth "rvl" image):
//   bytes 0-3, 4-7  width, height: uint32 little-endian
//   then            the stream: nibbles packed into 32-bit little-endian words, the first nibble
//                   in the word's top 4 bits; the last word is filled up with zero nibbles
// The stream is pairs (number of zero pixels, number of non-zero pixels) in row-major order, each
// pair followed by its non-zero pixels, each coded as the zigzag-mapped difference to the last
// non-zero pixel before it (0 before the first): 2d for d >= 0, -2d - 1 for d < 0. Every count
// and value is variable-length: 3 bits per nibble, least significant first, the nibble's top bit
// set when another follows. The last pair ends at the last pixel (its non-zero count is 0 when the
// image ends in zeros).
//
// The decoder takes exactly what the encoder writes, so an accepted payload re-encodes to the same
// bytes: a truncated, overlong or padded stream, a run past the end of the image, a count or value
// with superfluous nibbles, a zero value inside a non-zero run or an empty run are all errors.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"

namespace semfuse::wire {

// The size header, in bytes.
inline constexpr std::size_t kRvlHeaderBytes = 8;

// CV_16UC1 units -> payload. Fails on another type or an empty image.
Result<std::vector<uint8_t>> encodeRvl(const cv::Mat& units);

// The size the payload's header declares (nothing else is checked): what a caller compares with
// the size it expects, and bounds, before decodeRvl allocates the image.
Result<cv::Size> rvlDeclaredSize(const uint8_t* data, std::size_t size);

// Payload -> CV_16UC1 of the declared size, which must be `expected`. Every byte is checked; an
// error names the pixel where the stream went wrong.
Result<cv::Mat> decodeRvl(const uint8_t* data, std::size_t size, cv::Size expected);

}  // namespace semfuse::wire
