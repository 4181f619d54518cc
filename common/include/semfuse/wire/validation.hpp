#pragma once
// Checks that turn a malformed message into a precise error. Each names the field (`what`,
// e.g. "depth") and the measured numbers, so a rejected sample in the server's status says
// exactly what the sender got wrong. Cameras (intrinsics, poses) are checked by
// semfuse/core/camera_check.hpp, with its kMaxImageSide as the limit on the wire.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/camera_check.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::wire {

// "depth: image size 0x480 is empty" / "depth: image size 9000x480 exceeds the 8192-pixel limit".
Status validateImageSize(const std::string& what, int64_t width, int64_t height, uint32_t max_side = kMaxImageSide);

// A generated sequence whose _length exceeds _maximum or has no buffer (a truncated sample).
Status validateSequence(const std::string& what, uint32_t length, uint32_t maximum, const void* buffer);

// "depth: 614399 bytes for 640x480 16UC1, expected 614400".
Status validateDataSize(const std::string& what, std::size_t bytes, uint32_t width, uint32_t height,
                        const std::string& encoding, std::size_t bytes_per_pixel);

// "depth: unknown encoding 'rgb16' (known: 16UC1, 32FC1, png16)".
Status validateEncoding(const std::string& what, const std::string& encoding, const std::vector<std::string>& known);

// A compressed payload after cv::imdecode: empty = failed to decode; else size and type must match.
// `format` is "PNG" or "JPEG" for the message; expected_type e.g. CV_16UC1.
Status validateDecodedImage(const std::string& what, const std::string& format, const cv::Mat& decoded, uint32_t width,
                            uint32_t height, int expected_type);

// The size a PNG declares in its header (checked before decoding, so that a small payload cannot
// make the decoder allocate a huge image). Error when the bytes are not a PNG.
Result<cv::Size> pngDeclaredSize(const uint8_t* data, std::size_t size);
// Whether a PNG's chunks are all there: the signature, then chunks whose declared lengths each
// fit in what is left, the last one IEND (bytes after it are ignored, as decoders do). Checked before decoding because
// libpng reports a cut file on stderr, outside our log, before OpenCV gives up on it. Chunk CRCs
// are not checked here (libpng does).
Status pngChunksComplete(const uint8_t* data, std::size_t size);
// The same for a JPEG: the size in its first frame header (SOFn), found by walking the marker
// segments as a decoder does. Without it a 300-byte JPEG declaring 30000x30000 pixels makes
// OpenCV allocate gigabytes before the size can be compared with the frame's.
Result<cv::Size> jpegDeclaredSize(const uint8_t* data, std::size_t size);

// A segmentation may be smaller than its frame, never larger.
Status validateSegmentationSize(uint32_t seg_width, uint32_t seg_height, uint32_t frame_width, uint32_t frame_height);

// CV_32FC1 confidences within [0, 1]; NaN is out of range too.
Status validateConfidence(const cv::Mat& confidence);

// Every label id (CV_16UC1) is in the legend: reports the first bad id, where, and how many pixels.
Status validateLabels(const cv::Mat& labels, const LabelLegend& legend);

// "16UC1", "8UC3", ... (OpenCV's type names without the "CV_").
std::string typeName(int cv_type);

}  // namespace semfuse::wire
