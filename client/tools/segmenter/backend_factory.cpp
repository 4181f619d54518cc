#include "backend_factory.hpp"

#include <memory>

#include <spdlog/spdlog.h>

#include "semfuse/core/legend_io.hpp"
#include "semfuse/segmentation/dnn_segmenter.hpp"
#include "semfuse/segmentation/ground_truth.hpp"
#include "semfuse/segmentation/noise_model.hpp"

namespace semfuse::tools {
namespace {

Result<client::SegmentFunction> makeBase(const std::string& kind, const BackendOptions& o) {
  if (o.instances && (kind != "gt" || !o.labels_dir.empty()))
    return makeError("--instances needs the gt backend on the synthetic room (no --labels-dir)");
  if (kind == "gt") {
    if (o.labels_dir.empty()) {
      auto gt = std::make_shared<segmentation::SyntheticGroundTruth>(o.instances);
      return client::SegmentFunction([gt](const Frame& f) { return gt->segment(f); });
    }
    auto folder = std::make_shared<segmentation::LabelFolder>(o.labels_dir, o.labels_pattern);
    return client::SegmentFunction([folder](const Frame& f) { return folder->segment(f); });
  }
  if (kind == "dnn") {
    if (o.model.empty()) return makeError("the dnn backend needs --model FILE");
    auto layout = segmentation::parseLayout(o.layout);
    if (!layout) return makeError(layout.error());
    segmentation::DnnOptions dnn;
    dnn.model = o.model;
    dnn.input_width = o.input_size.at(0);
    dnn.input_height = o.input_size.at(1);
    dnn.layout = layout.value();
    dnn.mean = o.mean;
    dnn.scale = o.scale;
    dnn.output_name = o.output_name;
    if (!o.label_map.empty()) dnn.label_map = o.label_map;
    auto created = segmentation::DnnSegmenter::create(dnn);
    if (!created) return makeError(created.error());
    std::shared_ptr<segmentation::DnnSegmenter> net = std::move(created).value();
    spdlog::info("dnn: {} loaded, {} classes", o.model, net->classCount());
    // OpenCV's Net is not re-entrant; the Segmenter calls from one worker thread only.
    return client::SegmentFunction([net](const Frame& f) { return net->segment(f); });
  }
  return makeError("unknown backend '" + kind + "' (gt, dnn, noise)");
}

Result<std::vector<LabelId>> noiseCandidates(const BackendOptions& o) {
  std::vector<LabelId> ids;
  if (!o.noise_labels.empty()) {
    for (int id : o.noise_labels) {
      if (id <= 0 || id > 65535) return makeError("--noise-labels: " + std::to_string(id) + " is not a label id");
      ids.push_back(static_cast<LabelId>(id));
    }
    return ids;
  }
  auto legend = resolveLegend(o.legend);
  if (!legend) return makeError(legend.error());
  for (const auto& label : legend.value().labels) {
    if (label.id != kUnlabeled && !legend.value().isBackground(label.id)) ids.push_back(label.id);
  }
  return ids;
}

}  // namespace

Result<client::SegmentFunction> makeSegmentFunction(const BackendOptions& o) {
  if (o.backend != "noise") return makeBase(o.backend, o);
  if (o.base == "noise") return makeError("--base cannot be noise");
  auto base = makeBase(o.base, o);
  if (!base) return base;
  auto model = segmentation::parseNoiseModel(o.noise_model);
  if (!model) return makeError(model.error());
  auto candidates = noiseCandidates(o);
  if (!candidates) return makeError(candidates.error());
  segmentation::NoiseParams params{model.value(), o.noise, o.seed, std::move(candidates).value(), o.instance_erosion};
  if (params.candidates.size() < 2) return makeError("label noise needs at least two candidate labels");
  return client::SegmentFunction([inner = std::move(base).value(), params](const Frame& f) -> Result<Segmentation> {
    auto clean = inner(f);
    if (!clean) return clean;
    return segmentation::addLabelNoise(clean.value(), params, f.seq);
  });
}

}  // namespace semfuse::tools
