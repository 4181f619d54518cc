#include "semfuse/wire/validation.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace semfuse::wire {
namespace {

TEST(Validation, SegmentationLargerThanFrame) {
  EXPECT_TRUE(validateSegmentationSize(320, 240, 640, 480).ok());
  EXPECT_EQ(validateSegmentationSize(641, 480, 640, 480).error(),
            "segmentation: 641x480 is larger than its frame 640x480");
}

TEST(Validation, ConfidenceNaNIsOutOfRange) {
  cv::Mat confidence(2, 2, CV_32FC1, cv::Scalar(0.5f));
  EXPECT_TRUE(validateConfidence(confidence).ok());
  confidence.at<float>(1, 0) = std::nanf("");
  EXPECT_EQ(validateConfidence(confidence).error(), "confidence: value nan at (0, 1) outside [0, 1]");
  confidence.at<float>(1, 0) = -0.25f;
  EXPECT_EQ(validateConfidence(confidence).error(), "confidence: value -0.25 at (0, 1) outside [0, 1]");
}

TEST(Validation, LabelsOutsideTheLegendReportFirstIdAndCount) {
  const LabelLegend voc = *builtinLegend("voc");
  cv::Mat labels(3, 4, CV_16UC1, cv::Scalar(9));
  EXPECT_TRUE(validateLabels(labels, voc).ok());
  labels.at<uint16_t>(1, 2) = 21;
  labels.at<uint16_t>(2, 3) = 400;
  EXPECT_EQ(validateLabels(labels, voc).error(),
            "labels: 2 pixels with ids outside legend 'voc' (max id 20); first: id 21 at (2, 1)");
}

TEST(Validation, PngDeclaredSizeReadsTheHeader) {
  std::vector<uint8_t> header = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0,    13,
                                 'I',  'H', 'D', 'R', 0,    0,    0x02, 0x80, 0, 0, 0x01, 0xE0};
  auto size = pngDeclaredSize(header.data(), header.size());
  ASSERT_TRUE(size.ok()) << size.error();
  EXPECT_EQ(size.value(), cv::Size(640, 480));
  header[1] = 'X';
  EXPECT_FALSE(pngDeclaredSize(header.data(), header.size()).ok());
}

TEST(Validation, PngChunksCompleteFindsEveryCut) {
  std::vector<uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(30, 40, CV_16UC1, cv::Scalar(1234)), png));
  EXPECT_TRUE(pngChunksComplete(png.data(), png.size()).ok());
  // Cut anywhere after the signature: refused, naming what is missing (libpng would print to
  // stderr first). Every length from the signature to one byte short of the whole file.
  for (std::size_t cut = 8; cut < png.size(); ++cut) {
    const Status status = pngChunksComplete(png.data(), cut);
    ASSERT_FALSE(status.ok()) << "cut at " << cut;
    EXPECT_EQ(status.error().rfind("truncated: ", 0), 0u) << status.error();
  }
  EXPECT_EQ(pngChunksComplete(png.data(), png.size() - 12).error(),
            "truncated: no IEND chunk in " + std::to_string(png.size() - 12) + " bytes");
  // Bytes after IEND are ignored, as decoders do.
  std::vector<uint8_t> trailing(png);
  trailing.insert(trailing.end(), {1, 2, 3});
  EXPECT_TRUE(pngChunksComplete(trailing.data(), trailing.size()).ok());
  // A chunk that declares more than the file holds: IHDR says 2^31 bytes.
  std::vector<uint8_t> lying(png);
  lying[8] = 0x80;
  EXPECT_EQ(
      pngChunksComplete(lying.data(), lying.size()).error(),
      "truncated: chunk 'IHDR' at byte 8 declares 2147483661 bytes, " + std::to_string(png.size() - 20) + " left");
  EXPECT_FALSE(pngChunksComplete(png.data(), 7).ok());
}

TEST(Validation, JpegDeclaredSizeIsReadFromTheFrameHeader) {
  for (int progressive : {0, 1}) {
    std::vector<uint8_t> jpeg;
    ASSERT_TRUE(cv::imencode(".jpg", cv::Mat(10, 20, CV_8UC3, cv::Scalar(1, 2, 3)), jpeg,
                             {cv::IMWRITE_JPEG_PROGRESSIVE, progressive}));
    auto size = jpegDeclaredSize(jpeg.data(), jpeg.size());
    ASSERT_TRUE(size.ok()) << size.error();
    EXPECT_EQ(size.value(), cv::Size(20, 10));
    // Cut just after the SOI and the first segment: no frame header left.
    EXPECT_EQ(jpegDeclaredSize(jpeg.data(), 2 + 2 + ((jpeg[4] << 8) | jpeg[5])).error(),
              "JPEG ends before its frame header");
  }
  const std::vector<uint8_t> garbage(64, 0x17);
  EXPECT_EQ(jpegDeclaredSize(garbage.data(), garbage.size()).error(), "not a JPEG (no SOI marker)");
}

}  // namespace
}  // namespace semfuse::wire
