#include "eval_sequence.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>

#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>

#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/segmentation/dnn_segmenter.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::eval {
namespace {
namespace fs = std::filesystem;

std::string numbered(const std::string& stem, std::size_t i, const std::string& extension) {
  char name[64];
  std::snprintf(name, sizeof name, "%s-%06zu%s", stem.c_str(), i, extension.c_str());
  return name;
}

std::vector<LabelId> presentLabels(const std::vector<cv::Mat>& images) {
  std::set<LabelId> present;
  for (const cv::Mat& image : images)
    for (int r = 0; r < image.rows; ++r)
      for (int c = 0; c < image.cols; ++c)
        if (const LabelId id = image.at<uint16_t>(r, c); id != kUnlabeled) present.insert(id);
  return {present.begin(), present.end()};
}

Status writeImage(const fs::path& path, const cv::Mat& image) {
  try {
    if (!cv::imwrite(path.string(), image)) return makeError("cannot write " + path.string());
  } catch (const cv::Exception& e) {
    return makeError("cannot write " + path.string() + ": " + e.what());
  }
  return Status::Ok();
}

// A segmentation cached as labels (16-bit PNG) and confidence (16-bit PNG, 1/65535 steps).
bool readCachedSegmentation(const fs::path& stem, Segmentation& out) {
  if (!fs::exists(stem.string() + ".labels.png") || !fs::exists(stem.string() + ".confidence.png")) return false;
  const cv::Mat labels = cv::imread(stem.string() + ".labels.png", cv::IMREAD_UNCHANGED);
  const cv::Mat confidence = cv::imread(stem.string() + ".confidence.png", cv::IMREAD_UNCHANGED);
  if (labels.type() != CV_16UC1 || confidence.type() != CV_16UC1 || labels.size() != confidence.size()) return false;
  out.labels = labels;
  confidence.convertTo(out.confidence, CV_32FC1, 1.0 / 65535.0);
  return true;
}

Status writeCachedSegmentation(const fs::path& stem, const Segmentation& segmentation) {
  cv::Mat confidence;
  segmentation.confidence.convertTo(confidence, CV_16UC1, 65535.0);
  if (Status s = writeImage(stem.string() + ".labels.png", segmentation.labels); !s) return s;
  return writeImage(stem.string() + ".confidence.png", confidence);
}

// The network's output for the selected frames, from the cache or computed (and cached).
Result<std::vector<Segmentation>> segmentFrames(
    const datasets::SevenScenesReader& reader, const std::vector<std::size_t>& indices, const fs::path& model,
    int input_size, const fs::path& cache,
    const std::function<void(const std::string&, std::size_t, std::size_t)>& on_progress) {
  std::vector<Segmentation> out(indices.size());
  std::unique_ptr<segmentation::DnnSegmenter> network;
  std::size_t computed = 0;
  double network_seconds = 0.0;
  const std::string stem = "deeplab" + std::to_string(input_size);
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const fs::path cached = cache / numbered(stem, indices[k], "");
    if (!readCachedSegmentation(cached, out[k])) {
      if (!network) {
        segmentation::DnnOptions options;
        options.model = model;
        options.input_width = options.input_height = input_size;
        auto created = segmentation::DnnSegmenter::create(options);
        if (!created) return makeError(model.string() + ": " + created.error());
        network = std::move(created).value();
      }
      auto frame = reader.load(indices[k]);
      if (!frame) return makeError(frame.error());
      const auto start = std::chrono::steady_clock::now();
      auto segmentation = network->segment(frame.value());
      network_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++computed;
      if (!segmentation) return makeError("frame " + std::to_string(indices[k]) + ": " + segmentation.error());
      out[k] = std::move(segmentation).value();
      if (Status s = writeCachedSegmentation(cached, out[k]); !s) return makeError(s.error());
    }
    on_progress(stem, k + 1, indices.size());
  }
  if (computed > 0)
    spdlog::info("{}: {} frames segmented, {:.2f} s per frame (wall, this machine's load included); {} from the cache",
                 stem, computed, network_seconds / static_cast<double>(computed), indices.size() - computed);
  else spdlog::info("{}: all {} frames from the cache", stem, indices.size());
  return out;
}

}  // namespace

Result<EvalSequence> loadSynthetic(const SyntheticOptions& options, const fs::path& cache) {
  synthetic::SequenceConfig config;
  config.trajectory.frame_count = options.frames;
  config.trajectory.phase_rad = options.phase_rad;
  config.trajectory.radius = options.radius;
  config.trajectory.height = options.height;
  config.intrinsics = config.intrinsics.scaled(options.scale);
  config.noise = synthetic::DepthNoiseParams{};
  config.seed = options.seed;
  config.instances = true;
  synthetic::SyntheticSequence sequence(config);

  EvalSequence out;
  out.name = options.name;
  out.intrinsics = config.intrinsics;
  // Every option that changes a rendered frame names the cache folder: the trajectory is periodic
  // over `frames`, so frame i of a 150-frame run is not frame i of a 600-frame one.
  char key[160];
  std::snprintf(key, sizeof key, "%s-%df-%dx%d-phase%.3f-r%.3f-h%.3f-seed%llu", options.name.c_str(), options.frames,
                config.intrinsics.width, config.intrinsics.height, options.phase_rad, options.radius, options.height,
                static_cast<unsigned long long>(options.seed));
  const fs::path folder = cache / key;
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) return makeError("cannot create " + folder.string() + ": " + error.message());
  for (int i = 0; i < options.frames; ++i) {
    const fs::path depth_path = folder / numbered("depth", i, ".tiff");
    const fs::path labels_path = folder / numbered("labels", i, ".png");
    const fs::path instances_path = folder / numbered("instances", i, ".png");
    cv::Mat depth, labels, instances;
    if (fs::exists(depth_path) && fs::exists(labels_path) && fs::exists(instances_path)) {
      depth = cv::imread(depth_path.string(), cv::IMREAD_UNCHANGED);
      labels = cv::imread(labels_path.string(), cv::IMREAD_UNCHANGED);
      instances = cv::imread(instances_path.string(), cv::IMREAD_UNCHANGED);
    }
    if (depth.type() != CV_32FC1 || labels.type() != CV_16UC1 || instances.type() != CV_16UC1) {
      auto rendered = sequence.frameWithGroundTruth(i);
      if (!rendered) return makeError("synthetic frame " + std::to_string(i) + ": " + rendered.error());
      depth = rendered.value().first.depth;
      labels = rendered.value().second.labels;
      instances = rendered.value().second.instances;
      if (Status s = writeImage(depth_path, depth); !s) return makeError(s.error());
      if (Status s = writeImage(labels_path, labels); !s) return makeError(s.error());
      if (Status s = writeImage(instances_path, instances); !s) return makeError(s.error());
    }
    out.frames.push_back({depth, sequence.pose(i)});
    out.truth.push_back(labels);
    out.instances.push_back(instances);
  }
  out.present_labels = presentLabels(out.truth);
  return out;
}

Result<volume::LabeledVolume> integrateGeometry(const EvalSequence& sequence, const volume::VolumeParams& params) {
  volume::VolumeParams geometry_params = params;
  geometry_params.integrate_color = false;
  geometry_params.label_rule = volume::LabelRule::kEvidence;  // labels come later, per rule
  auto created = volume::LabeledVolume::create(geometry_params);
  if (!created) return makeError(created.error());
  volume::LabeledVolume volume = std::move(created).value();
  for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
    const EvalFrame& frame = sequence.frames[i];
    auto stats = volume::integrate(volume, frame.depth, cv::Mat(), sequence.intrinsics, frame.camera_to_world);
    if (!stats) return makeError(sequence.name + " frame " + std::to_string(i) + ": " + stats.error());
  }
  return volume;
}

Result<EvalSequence> loadSevenScenes(
    const SevenScenesOptions& options, const fs::path& cache,
    const std::function<void(const std::string&, std::size_t, std::size_t)>& on_progress) {
  if (options.stride < 1 || options.network_stride < 1 || options.network_stride % options.stride != 0)
    return makeError("strides must be at least 1 and the network stride a multiple of the frame stride");
  auto reader = datasets::SevenScenesReader::open(options.folder);
  if (!reader) return makeError(reader.error());
  const std::size_t count = std::min<std::size_t>(reader.value().count(), static_cast<std::size_t>(options.frames));
  std::vector<std::size_t> indices, network_indices;
  for (std::size_t i = 0; i < count; i += static_cast<std::size_t>(options.stride)) indices.push_back(i);
  for (std::size_t i = 0; i < count; i += static_cast<std::size_t>(options.network_stride))
    network_indices.push_back(i);
  // Position of dataset frame i in `frames` (i is a multiple of the stride).
  auto position = [&](std::size_t i) { return i / static_cast<std::size_t>(options.stride); };

  EvalSequence out;
  out.name = "7scenes";
  out.intrinsics = reader.value().intrinsics();
  for (std::size_t i : indices) {
    auto frame = reader.value().loadDepthOnly(i);
    if (!frame) return makeError(frame.error());
    if (!frame.value().camera_to_world) return makeError("7-Scenes frame " + std::to_string(i) + " has no pose");
    out.frames.push_back({frame.value().depth, *frame.value().camera_to_world});
  }
  const fs::path folder = cache / "7scenes";
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) return makeError("cannot create " + folder.string() + ": " + error.message());

  auto reference_labels =
      segmentFrames(reader.value(), network_indices, options.models / "ade20k_deeplabv3_mnv2_513_logits.pb", 513,
                    folder, on_progress);
  if (!reference_labels) return makeError(reference_labels.error());
  auto segmenter_labels =
      segmentFrames(reader.value(), network_indices, options.models / "ade20k_deeplabv3_mnv2_257_logits.pb", 257,
                    folder, on_progress);
  if (!segmenter_labels) return makeError(segmenter_labels.error());
  out.segmentations.resize(indices.size());  // empty where the networks did not run
  for (std::size_t k = 0; k < network_indices.size(); ++k)
    out.segmentations[position(network_indices[k])] = std::move(segmenter_labels.value()[k]);

  // The reference labeling: the stronger network's labels fused over every frame (majority rule,
  // so no single frame's confidence dominates), raycast back into each frame as its truth.
  auto geometry = integrateGeometry(out, options.params);
  if (!geometry) return makeError(geometry.error());
  volume::VolumeParams reference_params = options.params;
  reference_params.integrate_color = false;
  reference_params.label_rule = volume::LabelRule::kMajority;
  volume::LabeledVolume reference(reference_params);
  reference.mutableGeometryGrid().setTree(
      std::make_shared<volume::GeometryGrid::TreeType>(geometry.value().geometryGrid().tree()));
  for (std::size_t k = 0; k < network_indices.size(); ++k) {
    const Segmentation& s = reference_labels.value()[k];
    const EvalFrame& frame = out.frames[position(network_indices[k])];
    auto stats =
        volume::integrateLabels(reference, frame.depth, s.labels, s.confidence, out.intrinsics, frame.camera_to_world);
    if (!stats) return makeError(stats.error());
  }
  render::RaycastOptions raycast_options;
  raycast_options.layers = kLabelsLayer;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    auto images = render::raycast(reference, out.intrinsics, out.frames[k].camera_to_world, raycast_options);
    if (!images) return makeError("raycast of the reference labeling: " + images.error());
    out.truth.push_back(images.value().labels);
    on_progress("reference raycasts", k + 1, indices.size());
  }
  out.present_labels = presentLabels(out.truth);
  out.reference_labeling = std::make_shared<const volume::LabeledVolume>(std::move(reference));
  spdlog::info("7scenes: {} frames (stride {}, networks on every {}th), {} labels in the reference labeling",
               indices.size(), options.stride, options.network_stride, out.present_labels.size());
  return out;
}

}  // namespace semfuse::eval
