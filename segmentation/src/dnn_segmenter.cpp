#include "semfuse/segmentation/dnn_segmenter.hpp"

#include <cmath>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

namespace semfuse::segmentation {

struct DnnSegmenter::Net {
  cv::dnn::Net net;
};

Result<TensorLayout> parseLayout(const std::string& text) {
  if (text == "nchw") return TensorLayout::kNchw;
  if (text == "nhwc") return TensorLayout::kNhwc;
  return makeError("unknown tensor layout '" + text + "' (nchw, nhwc)");
}

DnnSegmenter::DnnSegmenter(DnnOptions options, std::unique_ptr<Net> net)
    : options_(std::move(options)), net_(std::move(net)) {}
DnnSegmenter::~DnnSegmenter() = default;

Result<std::unique_ptr<DnnSegmenter>> DnnSegmenter::create(const DnnOptions& options) {
  if (options.input_width < 1 || options.input_height < 1) return makeError("dnn: input size must be positive");
  auto net = std::make_unique<Net>();
  try {
    const std::string extension = options.model.extension().string();
    if (extension == ".onnx") net->net = cv::dnn::readNetFromONNX(options.model.string());
    else if (extension == ".pb") net->net = cv::dnn::readNetFromTensorflow(options.model.string());
    else return makeError("dnn: model must be a .pb (TensorFlow) or .onnx file: " + options.model.string());
  } catch (const cv::Exception& e) {
    return makeError("dnn: cannot load " + options.model.string() + ": " + e.what());
  }
  if (net->net.empty()) return makeError("dnn: " + options.model.string() + " holds no network");
  std::unique_ptr<DnnSegmenter> segmenter(new DnnSegmenter(options, std::move(net)));
  auto logits = segmenter->forward(cv::Mat(options.input_height, options.input_width, CV_8UC3, cv::Scalar::all(128)));
  if (!logits) return makeError(logits.error());
  segmenter->class_count_ = logits.value().size[0];
  if (options.label_map) {
    auto map = loadLabelMap(*options.label_map, segmenter->class_count_);
    if (!map) return makeError(map.error());
    segmenter->label_map_ = std::move(map).value();
  } else {
    segmenter->label_map_ = identityLabelMap(segmenter->class_count_);
  }
  return segmenter;
}

Result<cv::Mat> DnnSegmenter::forward(const cv::Mat& rgb) {
  cv::Mat resized;
  cv::resize(rgb, resized, cv::Size(options_.input_width, options_.input_height), 0, 0, cv::INTER_LINEAR);
  cv::Mat normalised;
  resized.convertTo(normalised, CV_32FC3, options_.scale, -options_.mean * options_.scale);
  cv::Mat blob;
  if (options_.layout == TensorLayout::kNchw) {
    blob = cv::dnn::blobFromImage(normalised);  // HWC -> 1xCxHxW, no further scaling
  } else {
    const int shape[] = {1, options_.input_height, options_.input_width, 3};
    blob = cv::Mat(4, shape, CV_32F, normalised.data).clone();  // interleaved pixels are NHWC already
  }
  cv::Mat out;
  try {
    net_->net.setInput(blob);
    out = options_.output_name.empty() ? net_->net.forward() : net_->net.forward(options_.output_name);
  } catch (const cv::Exception& e) {
    return makeError(std::string("dnn: forward pass failed: ") + e.what());
  }
  if (out.dims != 4 || out.size[0] != 1) return makeError("dnn: expected a 4-D logits output with batch 1");
  // Bring the logits into [classes][h][w] planes whatever the layout.
  if (options_.layout == TensorLayout::kNchw) {
    const int shape[] = {out.size[1], out.size[2], out.size[3]};
    return cv::Mat(3, shape, CV_32F, out.ptr<float>()).clone();
  }
  const int h = out.size[1], w = out.size[2], classes = out.size[3];
  const int shape[] = {classes, h, w};
  cv::Mat planes(3, shape, CV_32F);
  const float* src = out.ptr<float>();
  float* dst = planes.ptr<float>();
  for (int p = 0; p < h * w; ++p)
    for (int k = 0; k < classes; ++k)
      dst[static_cast<std::size_t>(k) * h * w + p] = src[static_cast<std::size_t>(p) * classes + k];
  return planes;
}

Result<Segmentation> DnnSegmenter::segment(const Frame& frame) {
  if (frame.color.empty()) return makeError("dnn: the frame has no colour image (camera sent --color-encoding none?)");
  return segmentImage(frame.color);
}

Result<Segmentation> DnnSegmenter::segmentImage(const cv::Mat& rgb) {
  if (rgb.empty() || rgb.type() != CV_8UC3) return makeError("dnn: needs a CV_8UC3 RGB image");
  auto logits = forward(rgb);
  if (!logits) return makeError(logits.error());
  const cv::Mat& planes = logits.value();
  const int classes = planes.size[0], h = planes.size[1], w = planes.size[2];
  const cv::Size size = rgb.size();
  // Two passes over upsampled class planes keep memory at a few image-sized buffers, whatever
  // the class count: the first finds each pixel's best logit, the second sums the softmax
  // denominator relative to it.
  cv::Mat best(size, CV_32FC1, cv::Scalar(-INFINITY));
  cv::Mat best_class(size, CV_16UC1, cv::Scalar(0));
  cv::Mat up;
  const auto plane = [&](int k) {
    return cv::Mat(h, w, CV_32F, const_cast<float*>(planes.ptr<float>()) + static_cast<std::size_t>(k) * h * w);
  };
  for (int k = 0; k < classes; ++k) {
    cv::resize(plane(k), up, size, 0, 0, cv::INTER_LINEAR);
    const cv::Mat better = up > best;
    up.copyTo(best, better);
    best_class.setTo(k, better);
  }
  cv::Mat denominator(size, CV_32FC1, cv::Scalar(0));
  for (int k = 0; k < classes; ++k) {
    cv::resize(plane(k), up, size, 0, 0, cv::INTER_LINEAR);
    cv::exp(up - best, up);
    denominator += up;
  }
  Segmentation result;
  cv::divide(1.0, denominator, result.confidence, CV_32F);  // exp(best - best) / sum
  result.labels.create(size, CV_16UC1);
  for (int r = 0; r < size.height; ++r) {
    const auto* cls = best_class.ptr<uint16_t>(r);
    auto* label = result.labels.ptr<uint16_t>(r);
    for (int c = 0; c < size.width; ++c) label[c] = label_map_[cls[c]];
  }
  return result;
}

}  // namespace semfuse::segmentation
