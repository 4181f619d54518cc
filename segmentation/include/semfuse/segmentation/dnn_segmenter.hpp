#pragma once
// Semantic segmentation with an OpenCV dnn network (TensorFlow .pb or ONNX): the frame's colour
// image is resized to the network input, normalised as (x - mean) * scale, run once, and the
// per-class logits are upsampled to the frame size; the label is the arg-max class mapped to the
// legend and the confidence its softmax probability.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/segmentation/label_map.hpp"

namespace semfuse::segmentation {

enum class TensorLayout { kNchw, kNhwc };

struct DnnOptions {
  std::filesystem::path model;  // .pb (TensorFlow) or .onnx
  int input_width = 257;
  int input_height = 257;
  TensorLayout layout = TensorLayout::kNchw;  // of the input and of the logits output
  double mean = 127.5;                        // x / 127.5 - 1 for the DeepLab models in ../shared/models
  double scale = 1.0 / 127.5;
  std::string output_name;                         // empty: the network's last layer
  std::optional<std::filesystem::path> label_map;  // empty: identity
};

Result<TensorLayout> parseLayout(const std::string& text);

class DnnSegmenter {
 public:
  // Loads the network and runs it once on a grey image, which both checks that it works and
  // tells the number of classes (the label map is validated against it).
  static Result<std::unique_ptr<DnnSegmenter>> create(const DnnOptions& options);
  ~DnnSegmenter();

  // frame.color must be present (CV_8UC3 RGB); labels and confidence come at its size.
  Result<Segmentation> segment(const Frame& frame);
  // Same on a bare RGB image.
  Result<Segmentation> segmentImage(const cv::Mat& rgb);

  int classCount() const { return class_count_; }

 private:
  struct Net;
  DnnSegmenter(DnnOptions options, std::unique_ptr<Net> net);
  Result<cv::Mat> forward(const cv::Mat& rgb);  // logits as [classes][h][w] planes, CV_32F

  DnnOptions options_;
  std::unique_ptr<Net> net_;
  int class_count_ = 0;
  LabelMap label_map_;
};

}  // namespace semfuse::segmentation
