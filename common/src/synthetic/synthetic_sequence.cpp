#include "semfuse/synthetic/synthetic_sequence.hpp"

#include <cmath>
#include <string>
#include <utility>

#include <opencv2/core.hpp>

namespace semfuse::synthetic {

SyntheticSequence::SyntheticSequence(SequenceConfig config)
    : config_(std::move(config)), scene_(makeRoom(config_.room)) {}

Status SyntheticSequence::checkIndex(int index) const {
  if (index < 0 || index >= frameCount())
    return makeError("synthetic frame index " + std::to_string(index) + " outside [0, " + std::to_string(frameCount()) +
                     ")");
  return Status::Ok();
}

Result<RenderedView> SyntheticSequence::view(int index) const {
  if (Status ok = checkIndex(index); !ok) return makeError(ok.error());
  return renderView(scene_, config_.intrinsics, pose(index));
}

Stamp SyntheticSequence::stampOf(int index) const {
  const double t = config_.frame_rate_hz > 0.0 ? index / config_.frame_rate_hz : 0.0;
  Stamp stamp;
  stamp.sec = static_cast<int32_t>(std::floor(t));
  stamp.nanosec = static_cast<uint32_t>(std::llround((t - stamp.sec) * 1e9) % 1000000000LL);
  return stamp;
}

Frame SyntheticSequence::makeFrame(const RenderedView& view, int index, bool with_pose) const {
  Frame frame;
  frame.camera_id = config_.camera_id;
  frame.seq = static_cast<uint64_t>(index);
  frame.stamp = stampOf(index);
  frame.intrinsics = view.intrinsics;
  frame.depth = config_.noise ? applyDepthNoise(view, *config_.noise, config_.seed, frame.seq) : view.depth.clone();
  frame.color = view.color.clone();
  if (with_pose) frame.camera_to_world = view.camera_to_world;
  return frame;
}

Segmentation SyntheticSequence::makeSegmentation(const RenderedView& view, int index) const {
  Segmentation segmentation;
  segmentation.camera_id = config_.camera_id;
  segmentation.frame_seq = static_cast<uint64_t>(index);
  segmentation.segmenter_id = config_.segmenter_id;
  segmentation.stamp = stampOf(index);
  segmentation.labels = view.labels.clone();
  cv::Mat labeled = view.labels > 0;  // 255 where labeled
  labeled.convertTo(segmentation.confidence, CV_32FC1, 1.0 / 255.0);
  if (config_.instances) segmentation.instances = view.instances.clone();
  return segmentation;
}

Result<Frame> SyntheticSequence::frame(int index, bool with_pose) const {
  auto rendered = view(index);
  if (!rendered) return makeError(rendered.error());
  return makeFrame(rendered.value(), index, with_pose);
}

Result<Segmentation> SyntheticSequence::groundTruth(int index) const {
  auto rendered = view(index);
  if (!rendered) return makeError(rendered.error());
  return makeSegmentation(rendered.value(), index);
}

Result<std::pair<Frame, Segmentation>> SyntheticSequence::frameWithGroundTruth(int index, bool with_pose) const {
  auto rendered = view(index);
  if (!rendered) return makeError(rendered.error());
  return std::make_pair(makeFrame(rendered.value(), index, with_pose), makeSegmentation(rendered.value(), index));
}

}  // namespace semfuse::synthetic
