#pragma once
// Builds semfuse-segmenter's segment function from its command line: a base backend (gt, labels,
// dnn), optionally wrapped in label noise.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "semfuse/client/segmenter.hpp"
#include "semfuse/core/result.hpp"

namespace semfuse::tools {

struct BackendOptions {
  std::string backend = "gt";  // gt | dnn | noise
  std::string base = "gt";     // noise: the backend it corrupts (gt or dnn)
  // gt
  std::string labels_dir;  // empty: the synthetic room; else label images per frame
  std::string labels_pattern = "frame-{:06d}.label.png";
  bool instances = false;  // the synthetic room's instance maps too (a panoptic segmenter)
  // noise
  std::string noise_model = "pixel";
  double noise = 0.3;
  uint64_t seed = 0;
  std::string legend = "synthetic";  // the candidate wrong labels: this legend's non-zero ids
  std::vector<int> noise_labels;     // explicit candidate ids instead of the legend's
  int instance_erosion = 0;          // pixels off every instance mask's border
  // dnn
  std::string model;
  std::vector<int> input_size{257, 257};
  std::string layout = "nchw";
  double mean = 127.5;
  double scale = 1.0 / 127.5;
  std::string output_name;
  std::string label_map;
};

Result<client::SegmentFunction> makeSegmentFunction(const BackendOptions& options);

}  // namespace semfuse::tools
