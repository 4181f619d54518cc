#include "semfuse/wire/message_codecs.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace semfuse::wire {
namespace {

Segmentation makeSegmentation() {
  Segmentation seg;
  seg.camera_id = "cam0";
  seg.frame_seq = 99;
  seg.segmenter_id = "dnn";
  seg.stamp = {3, 4};
  seg.labels.create(6, 8, CV_16UC1);
  seg.confidence.create(6, 8, CV_32FC1);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) {
      seg.labels.at<uint16_t>(y, x) = static_cast<uint16_t>((x * 7 + y) % 21);
      seg.confidence.at<float>(y, x) = static_cast<float>((x + 8 * y) % 256) / 255.0f;  // exact in 8 bits
    }
  }
  return seg;
}

TEST(SegmentationCodec, RoundTripsEveryConfidenceEncoding) {
  const Segmentation in = makeSegmentation();
  for (const std::string encoding : {"8UC1", "32FC1", ""}) {
    Segmentation source = in;
    if (encoding.empty()) source.confidence.release();
    auto encoded = encodeSegmentation(source, encoding);
    ASSERT_TRUE(encoded.ok()) << encoded.error();
    auto out = decodeSegmentation(encoded.value().msg());
    ASSERT_TRUE(out.ok()) << encoding << ": " << out.error();
    EXPECT_EQ(out.value().camera_id, "cam0");
    EXPECT_EQ(out.value().frame_seq, 99u);
    EXPECT_EQ(out.value().segmenter_id, "dnn");
    EXPECT_EQ(cv::norm(in.labels, out.value().labels, cv::NORM_INF), 0.0);
    const cv::Mat expected = encoding.empty() ? cv::Mat(6, 8, CV_32FC1, cv::Scalar(1.0f)) : in.confidence;
    EXPECT_LT(cv::norm(expected, out.value().confidence, cv::NORM_INF), 1e-6) << encoding;
  }
}

TEST(SegmentationCodec, RejectsBadSizesEncodingsAndConfidence) {
  auto encoded = encodeSegmentation(makeSegmentation(), "32FC1");
  ASSERT_TRUE(encoded.ok());
  auto& msg = encoded.value().msg();
  msg.labels._length -= 1;
  EXPECT_EQ(decodeSegmentation(msg).error(), "labels: 47 labels for 8x6, expected 48");
  msg.labels._length += 1;
  reinterpret_cast<float*>(msg.confidence._buffer)[9] = 1.5f;
  EXPECT_EQ(decodeSegmentation(msg).error(), "confidence: value 1.5 at (1, 1) outside [0, 1]");
  msg.confidence_encoding = const_cast<char*>("16UC1");
  EXPECT_EQ(decodeSegmentation(msg).error(), "confidence: unknown encoding '16UC1' (known: \"\", 8UC1, 32FC1)");
  msg.confidence_encoding = const_cast<char*>("8UC1");
  EXPECT_EQ(decodeSegmentation(msg).error(), "confidence: 192 bytes for 8x6 8UC1, expected 48");
  msg.width = 9000;
  EXPECT_EQ(decodeSegmentation(msg).error(), "segmentation: image size 9000x6 exceeds the 8192-pixel limit");
}

// Instance 5 on the left half, 9 on the right, none on the bottom row.
cv::Mat twoInstances() {
  cv::Mat ids(6, 8, CV_16UC1, cv::Scalar(0));
  ids(cv::Rect(0, 0, 4, 5)).setTo(5);
  ids(cv::Rect(4, 0, 4, 5)).setTo(9);
  return ids;
}

TEST(SegmentationCodec, CarriesAPanopticInstanceMapAndNoneForClassOnlySegmenters) {
  Segmentation in = makeSegmentation();
  auto class_only = decodeSegmentation(encodeSegmentation(in).value().msg());
  ASSERT_TRUE(class_only.ok()) << class_only.error();
  EXPECT_TRUE(class_only.value().instances.empty());

  in.instances = twoInstances();
  auto encoded = encodeSegmentation(in);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  EXPECT_EQ(encoded.value().msg().instances._length, 48u);
  auto out = decodeSegmentation(encoded.value().msg());
  ASSERT_TRUE(out.ok()) << out.error();
  ASSERT_EQ(out.value().instances.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(in.instances, out.value().instances, cv::NORM_INF), 0.0);
  EXPECT_EQ(out.value().instances.at<uint16_t>(2, 6), 9);

  Segmentation wrong_size = in;
  wrong_size.instances = cv::Mat(3, 4, CV_16UC1, cv::Scalar(1));
  EXPECT_FALSE(encodeSegmentation(wrong_size).ok());
}

TEST(SegmentationCodec, RejectsAnInstanceMapOfAnotherSizeOrWithoutLabels) {
  Segmentation in = makeSegmentation();
  in.instances = twoInstances();
  auto encoded = encodeSegmentation(in);
  ASSERT_TRUE(encoded.ok());
  auto& msg = encoded.value().msg();
  msg.instances._length = 40;
  EXPECT_EQ(decodeSegmentation(msg).error(), "instances: 40 ids for 8x6 labels, expected 48 (or none)");
  msg.instances._length = 48;
  for (uint32_t i = 0; i < msg.labels._length; ++i) msg.labels._buffer[i] = 0;
  EXPECT_EQ(decodeSegmentation(msg).error(),
            "instances: 40 pixels name an instance but none has a label (0 = unlabeled): send each instance's "
            "class in labels");
  msg.labels._buffer[47] = 3;  // a label where no instance is: still none on an instance
  EXPECT_FALSE(decodeSegmentation(msg).ok());
  msg.labels._buffer[0] = 3;  // one labeled instance pixel: the rest are ignored by the map, not refused
  EXPECT_TRUE(decodeSegmentation(msg).ok());
}

TEST(TrackedPoseCodec, RoundTripAndUnknownState) {
  TrackedPose in;
  in.camera_id = "cam1";
  in.seq = 5;
  in.state = PoseState::kTracked;
  in.posed = true;
  in.camera_to_world.translation() = Eigen::Vector3d(1, 2, 3);
  in.inlier_ratio = 0.75f;
  in.iterations = 12;
  auto encoded = encodeTrackedPose(in);
  auto out = decodeTrackedPose(encoded.msg());
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().state, PoseState::kTracked);
  EXPECT_EQ(out.value().camera_to_world.matrix(), in.camera_to_world.matrix());
  EXPECT_FLOAT_EQ(out.value().inlier_ratio, 0.75f);
  EXPECT_EQ(out.value().iterations, 12u);
  encoded.msg().state = 9;
  EXPECT_EQ(decodeTrackedPose(encoded.msg()).error(),
            "tracked pose: unknown state 9 (known: 0 given, 1 tracked, 2 refined, 3 lost)");
}

TEST(ObjectEventsCodec, UnknownKindAndBrokenSequenceAreRefused) {
  ObjectEvents in;
  in.update = 3;
  in.events = {{ObjectEventKind::kSplit, 6, 5, {13, 14}}};
  auto encoded = encodeObjectEvents(in);
  ASSERT_TRUE(decodeObjectEvents(encoded.msg()).ok());
  // A message decoded in place shares the encoder's buffers: break a copy of the entry.
  semfuse_msg_dds__ObjectEvent_ entry = encoded.msg().events._buffer[0];
  semfuse_msg_dds__ObjectEvents_ msg = encoded.msg();
  msg.events._buffer = &entry;
  entry.kind = 4;
  EXPECT_EQ(decodeObjectEvents(msg).error(),
            "object events: event 0 has unknown kind 4 (known: 0 appeared, 1 merged, 2 split, 3 vanished)");
  entry.kind = 2;
  entry.others._buffer = nullptr;
  EXPECT_FALSE(decodeObjectEvents(msg).ok());
  msg.events._length = 2;  // more entries than the buffer holds
  msg.events._maximum = 1;
  EXPECT_FALSE(decodeObjectEvents(msg).ok());
}

TEST(LegendCodec, RoundTripsBuiltinLegendAndRejectsDuplicates) {
  const LabelLegend in = *builtinLegend("ade20k");
  auto encoded = encodeLegend(in);
  auto out = decodeLegend(encoded.msg());
  ASSERT_TRUE(out.ok()) << out.error();
  ASSERT_EQ(out.value().labels.size(), 151u);
  EXPECT_EQ(out.value().name, "ade20k");
  EXPECT_EQ(out.value().find(20)->name, "chair");
  EXPECT_EQ(out.value().find(20)->rgb, in.find(20)->rgb);
  EXPECT_EQ(out.value().background_ids, in.background_ids);
  encoded.msg().labels._buffer[3].id = 2;
  EXPECT_EQ(decodeLegend(encoded.msg()).error(), "legend 'ade20k': label id 2 appears twice");
}

}  // namespace
}  // namespace semfuse::wire
