#include "semfuse/segmentation/ground_truth.hpp"

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/view_renderer.hpp"

namespace semfuse::segmentation {

// Geometry and labels of the room do not depend on its texture seed, so the default room has
// exactly the labels of whatever room semfuse-camera rendered.
SyntheticGroundTruth::SyntheticGroundTruth(bool with_instances)
    : scene_(synthetic::makeRoom()), with_instances_(with_instances) {}

Result<Segmentation> SyntheticGroundTruth::segment(const Frame& frame) const {
  if (!frame.camera_to_world) {
    return makeError("gt: frame " + std::to_string(frame.seq) + " has no pose; ground truth needs one");
  }
  auto view = synthetic::renderView(scene_, frame.intrinsics, *frame.camera_to_world);
  if (!view) return makeError("gt: " + view.error());
  Segmentation result;
  result.labels = view.value().labels;
  result.confidence = cv::Mat(result.labels.size(), CV_32FC1, cv::Scalar(1.0F));
  if (with_instances_) result.instances = view.value().instances;
  return result;
}

LabelFolder::LabelFolder(std::filesystem::path folder, std::string pattern)
    : folder_(std::move(folder)), pattern_(std::move(pattern)) {}

std::filesystem::path LabelFolder::fileFor(uint64_t seq) const {
  return folder_ / fmt::format(fmt::runtime(pattern_), seq);
}

Result<Segmentation> LabelFolder::segment(const Frame& frame) const {
  const auto file = fileFor(frame.seq);
  const cv::Mat image = cv::imread(file.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (image.empty()) return makeError("labels: cannot read " + file.string());
  Segmentation result;
  image.convertTo(result.labels, CV_16UC1);
  result.confidence = cv::Mat(result.labels.size(), CV_32FC1, cv::Scalar(1.0F));
  return result;
}

}  // namespace semfuse::segmentation
