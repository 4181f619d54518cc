#pragma once
// ROS 2 standard messages (sensor_msgs Image / CompressedImage / CameraInfo, geometry_msgs
// TransformStamped, std_msgs Header) <-> OpenCV / core types, so a ROS 2 camera can feed semfuse.
// Colour images come out in RGB order (as everywhere in semfuse), whatever the ROS encoding.
#include <cstddef>
#include <string>
#include <vector>

#include <geometry_msgs.h>
#include <sensor_msgs.h>
#include <std_msgs.h>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/wire/owned_message.hpp"

namespace semfuse::wire {

using OwnedImage = OwnedMessage<sensor_msgs_msg_dds__Image_>;
using OwnedCameraInfo = OwnedMessage<sensor_msgs_msg_dds__CameraInfo_>;
using OwnedTransform = OwnedMessage<geometry_msgs_msg_dds__TransformStamped_>;

// Image encodings read: 16UC1, mono16, 32FC1, mono8, 8UC1, rgb8, bgr8, 8UC3 (taken as RGB),
// rgba8, bgra8. Returns CV_16UC1, CV_32FC1, CV_8UC1 or CV_8UC3 (RGB). Checks step, data size,
// the size bound and endianness (big-endian data is swapped).
const std::vector<std::string>& rosImageEncodings();
Result<cv::Mat> imageToMat(const sensor_msgs_msg_dds__Image_& msg);
// Depth image in metres: 16UC1/mono16 are millimetres (REP 118), 32FC1 metres.
Result<cv::Mat> depthImageToMetres(const sensor_msgs_msg_dds__Image_& msg);
// CV_16UC1 -> "16UC1", CV_32FC1 -> "32FC1", CV_8UC1 -> "mono8", CV_8UC3 (RGB) -> "rgb8" or
// "bgr8" (channels swapped for bgr8). Little-endian, rows packed (step = width * pixel size).
Result<OwnedImage> matToImage(const cv::Mat& image, const std::string& encoding, Stamp stamp,
                              const std::string& frame_id);

// CompressedImage with format containing "jpeg"/"jpg" or "png" (e.g. "rgb8; jpeg compressed bgr8").
// Colour -> CV_8UC3 RGB; a 16-bit PNG -> CV_16UC1. ("compressedDepth" is refused: its payload
// starts with a header of its own, which compressedDepthToMetres reads.)
Result<cv::Mat> compressedImageToMat(const sensor_msgs_msg_dds__CompressedImage_& msg);

// A depth image as ROS 2's compressed_depth_image_transport sends it, in metres (CV_32FC1, 0 = no
// depth). Format "<encoding>; compressedDepth <png|rvl>" (a bare "compressedDepth" is PNG, as
// that transport reads it). The data: a 12-byte configuration header (int32 0, "inverse depth";
// float32 quantisation parameters a, b), then a 16-bit PNG or an RVL payload (rvl_codec.hpp) of
// the image's size. Encoding 16UC1 / mono16: the values are millimetres; 32FC1: they are the
// quantised inverse depth, depth = a / (value - b). Also a plain 16-bit PNG of millimetres
// (compressed_image_transport's "16UC1; png compressed"). Every value is little-endian.
Result<cv::Mat> compressedDepthToMetres(const sensor_msgs_msg_dds__CompressedImage_& msg);
// Millimetres (CV_16UC1) -> "16UC1; compressedDepth <compression>" for "png" or "rvl", as that
// transport writes it: what tests and the fuzz seeds send a server.
Result<OwnedMessage<sensor_msgs_msg_dds__CompressedImage_>> compressedDepthFromMillimetres(
    const cv::Mat& millimetres, const std::string& compression, Stamp stamp, const std::string& frame_id);
// The size of compressedDepth's configuration header.
inline constexpr std::size_t kCompressedDepthHeaderBytes = 12;

// K = [fx 0 cx; 0 fy cy; 0 0 1] from k[0], k[4], k[2], k[5]; validated like any intrinsics.
Result<PinholeIntrinsics> intrinsicsFromCameraInfo(const sensor_msgs_msg_dds__CameraInfo_& msg);
// plumb_bob with no distortion, R = I, P = [K | 0].
OwnedCameraInfo cameraInfoFromIntrinsics(const PinholeIntrinsics& intrinsics, Stamp stamp, const std::string& frame_id);

// Transform (translation + unit quaternion) -> Pose. The quaternion must have norm 1 within 1e-3.
Result<Pose> poseFromTransform(const geometry_msgs_msg_dds__Transform_& transform);
OwnedTransform transformFromPose(const Pose& pose, Stamp stamp, const std::string& frame_id,
                                 const std::string& child_frame_id);

// Header fields: the frame id is kept by `owner` (any OwnedMessage).
template <typename Msg>
void fillHeader(OwnedMessage<Msg>& owner, std_msgs_msg_dds__Header_& header, Stamp stamp, const std::string& frame_id) {
  header.stamp.sec = stamp.sec;
  header.stamp.nanosec = stamp.nanosec;
  header.frame_id = owner.keepString(frame_id);
}
inline Stamp stampOf(const std_msgs_msg_dds__Header_& header) { return {header.stamp.sec, header.stamp.nanosec}; }
// The system clock now, as a ROS time stamp.
Stamp stampNow();

}  // namespace semfuse::wire
