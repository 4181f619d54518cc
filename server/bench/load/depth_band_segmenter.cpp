#include "depth_band_segmenter.hpp"

#include <algorithm>

#include <opencv2/core.hpp>

namespace semfuse::bench::load {

std::vector<LabelId> foregroundLabels(const LabelLegend& legend, std::size_t count) {
  std::vector<LabelId> ids;
  for (const auto& label : legend.labels) {
    if (ids.size() == count) break;
    if (label.id != kUnlabeled && !legend.isBackground(label.id)) ids.push_back(label.id);
  }
  return ids;
}

client::SegmentFunction depthBandSegmenter(std::vector<LabelId> labels) {
  return [labels = std::move(labels)](const Frame& frame) -> Result<Segmentation> {
    if (labels.empty()) return makeError("the legend has no foreground label");
    Segmentation out;
    out.labels = cv::Mat(frame.depth.size(), CV_16UC1, cv::Scalar(0));
    const int third = std::max(1, frame.depth.cols / 3);
    for (int y = 0; y < frame.depth.rows; ++y) {
      const float* depth = frame.depth.ptr<float>(y);
      auto* label = out.labels.ptr<uint16_t>(y);
      for (int x = 0; x < frame.depth.cols; ++x) {
        if (!(depth[x] > 0.0F)) continue;  // no depth (0 or NaN): unlabeled
        const auto band = static_cast<std::size_t>(depth[x] * 4.0F);
        label[x] = labels[(band + static_cast<std::size_t>(x / third)) % labels.size()];
      }
    }
    return out;
  };
}

}  // namespace semfuse::bench::load
