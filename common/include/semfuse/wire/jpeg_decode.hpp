#pragma once
// JPEG to RGB through libjpeg(-turbo) directly.
//
// cv::imdecode hands back BGR, which it makes from libjpeg's RGB with a byte-by-byte swap loop;
// the frame codec then swapped it back to RGB. On 640x480 colour at 30 Hz per camera the two
// swaps cost the server more CPU than the decoding itself (a profile of the 2-camera ingest
// benchmark). Decoding straight into an RGB image skips both.
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "semfuse/core/result.hpp"

namespace semfuse::wire {

// Progressive JPEGs can carry any number of scans, each a full pass over the image: a small
// payload with thousands of scans keeps a decoder busy for seconds. Real encoders write about
// ten; more than this is refused.
inline constexpr int kMaxJpegScans = 100;

// Decodes `size` bytes of JPEG into a CV_8UC3 RGB image of exactly `expected` size (the caller
// has bounded it: jpegDeclaredSize and the frame's own size). Greyscale JPEGs come out as RGB.
// A payload that libjpeg cannot decode, that decodes to another size or that has more than
// kMaxJpegScans scans is an error with libjpeg's message. So is a payload cut short or with
// damaged entropy-coded data ("JPEG payload does not decode: damaged data (Premature end of JPEG
// file)"), which cv::imdecode and libjpeg itself would accept, filling in made-up pixels. Other
// libjpeg warnings (harmless: extraneous bytes before a marker, an unknown JFIF revision) are
// counted in `warnings` when given.
Result<cv::Mat> decodeJpegRgb(const uint8_t* data, std::size_t size, cv::Size expected, int* warnings = nullptr);
// The same, except that a greyscale JPEG comes out as CV_8UC1 (ROS compressed images keep their
// channel count).
Result<cv::Mat> decodeJpegRgbOrGrey(const uint8_t* data, std::size_t size, cv::Size expected, int* warnings = nullptr);

}  // namespace semfuse::wire
