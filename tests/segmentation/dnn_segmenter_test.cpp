// The dnn backend on real data: the VOC DeepLab model of ../shared/models on 7-Scenes kitchen frames.
#include <algorithm>
#include <iostream>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/segmentation/dnn_segmenter.hpp"
#include "shared_data.hpp"

namespace semfuse::segmentation {
namespace {

std::filesystem::path vocModel() { return testing::sharedDir() / "models" / "deeplabv3_mnv2_voc_257_opencv.onnx"; }

DnnOptions vocOptions() {
  DnnOptions o;
  o.model = vocModel();
  o.input_width = o.input_height = 257;
  o.layout = TensorLayout::kNhwc;
  return o;
}

TEST(DnnSegmenter, VocModelOnKitchenFrames) {
  SEMFUSE_REQUIRE_SHARED_DIR(testing::redkitchenDir());
  SEMFUSE_REQUIRE_SHARED_DIR(vocModel());
  auto reader = datasets::SevenScenesReader::open(testing::redkitchenDir());
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto created = DnnSegmenter::create(vocOptions());
  ASSERT_TRUE(created.ok()) << created.error();
  DnnSegmenter& net = *created.value();
  EXPECT_EQ(net.classCount(), 21);

  std::map<int, long> histogram;
  for (std::size_t index : {0u, 200u, 400u}) {
    auto frame = reader.value().load(index);
    ASSERT_TRUE(frame.ok()) << frame.error();
    auto result = net.segment(frame.value());
    ASSERT_TRUE(result.ok()) << result.error();
    const Segmentation& s = result.value();
    ASSERT_EQ(s.labels.size(), frame.value().color.size());
    ASSERT_EQ(s.labels.type(), CV_16UC1);
    ASSERT_EQ(s.confidence.type(), CV_32FC1);
    double min_conf = 0, max_conf = 0;
    cv::minMaxLoc(s.confidence, &min_conf, &max_conf);
    // A softmax maximum over 21 classes is at least 1/21.
    EXPECT_GE(min_conf, 1.0 / 21 - 1e-4);
    EXPECT_LE(max_conf, 1.0 + 1e-5);
    for (auto it = s.labels.begin<uint16_t>(); it != s.labels.end<uint16_t>(); ++it) ++histogram[*it];
  }
  std::vector<std::pair<long, int>> ranked;
  for (const auto& [label, count] : histogram) ranked.emplace_back(count, label);
  std::sort(ranked.rbegin(), ranked.rend());
  for (const auto& [count, label] : ranked) std::cout << "VOC class " << label << ": " << count << " pixels\n";
  // What the model really says for these kitchen views (measured: ~92% background, ~6% chair,
  // ~2% dining table, nothing else): cupboards, walls and appliances are not VOC classes.
  const double total = 3.0 * 640 * 480;
  ASSERT_GE(ranked.size(), 3u);
  EXPECT_EQ(ranked[0].second, 0) << "background should dominate";
  std::vector<int> objects;
  for (const auto& [count, label] : ranked)
    if (label != 0 && count > 0.01 * total) objects.push_back(label);
  std::sort(objects.begin(), objects.end());
  EXPECT_EQ(objects, (std::vector<int>{9, 11})) << "chair (9) and dining table (11) should be the object classes";
}

TEST(DnnSegmenter, Ade20kTensorflowModelOnAKitchenFrame) {
  const auto model = testing::sharedDir() / "models" / "ade20k_deeplabv3_mnv2_257_logits.pb";
  SEMFUSE_REQUIRE_SHARED_DIR(testing::redkitchenDir());
  SEMFUSE_REQUIRE_SHARED_DIR(model);
  auto reader = datasets::SevenScenesReader::open(testing::redkitchenDir());
  ASSERT_TRUE(reader.ok()) << reader.error();
  DnnOptions options;
  options.model = model;
  options.layout = TensorLayout::kNchw;
  auto created = DnnSegmenter::create(options);
  ASSERT_TRUE(created.ok()) << created.error();
  EXPECT_EQ(created.value()->classCount(), 150);
  auto frame = reader.value().load(0);
  ASSERT_TRUE(frame.ok()) << frame.error();
  auto result = created.value()->segment(frame.value());
  ASSERT_TRUE(result.ok()) << result.error();
  std::map<int, long> histogram;
  for (auto it = result.value().labels.begin<uint16_t>(); it != result.value().labels.end<uint16_t>(); ++it)
    ++histogram[*it];
  std::vector<std::pair<long, int>> ranked;
  for (const auto& [label, count] : histogram) ranked.emplace_back(count, label);
  std::sort(ranked.rbegin(), ranked.rend());
  for (std::size_t i = 0; i < std::min<std::size_t>(8, ranked.size()); ++i)
    std::cout << "ADE20K class " << ranked[i].second << ": " << ranked[i].first << " pixels\n";
  // Measured on frame 0: wall ~45%, then "bar" (78), other, windowpane, floor ~10%, cabinet ~2%.
  // A kitchen has walls first and floor and cabinets among its real classes.
  EXPECT_EQ(ranked.front().second, 1) << "wall should be the largest class";
  const auto share = [&](int label) { return histogram[label] / (640.0 * 480.0); };
  EXPECT_GT(share(4), 0.05) << "floor";
  EXPECT_GT(share(11), 0.01) << "cabinet";
}

TEST(DnnSegmenter, RejectsAFrameWithoutColourAndAMissingModel) {
  DnnOptions missing = vocOptions();
  missing.model = "/nonexistent/model.onnx";
  EXPECT_FALSE(DnnSegmenter::create(missing).ok());
  DnnOptions wrong_kind = vocOptions();
  wrong_kind.model = "/tmp/model.caffemodel";
  EXPECT_FALSE(DnnSegmenter::create(wrong_kind).ok());
}

}  // namespace
}  // namespace semfuse::segmentation
