#pragma once
// A small labeled map for the query fuzz target and the map-file seeds: a 5 cm volume with two
// labeled walls at different depths seen from one pose, so raycasts, regions, objects and
// meshes all have something to find. `pixels_across` scales the view (and the file size).
#include <cstdio>
#include <cstdlib>

#include <opencv2/core.hpp>

#include "semfuse/core/legend.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::fuzz {

inline volume::LabeledVolume makeTinyMap(int pixels_across = 32) {
  volume::VolumeParams params;
  params.voxel_size = 0.05;
  params.truncation = 0.2;
  params.integrate_color = true;
  auto created = volume::LabeledVolume::create(params);
  if (!created) {
    std::fprintf(stderr, "tiny map: %s\n", created.error().c_str());
    std::abort();
  }
  volume::LabeledVolume map = std::move(created).value();
  const int w = pixels_across, h = pixels_across * 3 / 4;
  const PinholeIntrinsics k{w, h, 20.0, 20.0, (w - 1) / 2.0, (h - 1) / 2.0};
  cv::Mat depth(h, w, CV_32FC1), labels(h, w, CV_16UC1), confidence(h, w, CV_32FC1, cv::Scalar(0.9f));
  cv::Mat color(h, w, CV_8UC3, cv::Scalar(200, 120, 40));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // Left half: a wall 1.0 m away (label 5), right half 1.5 m away (label 9).
      depth.at<float>(y, x) = x < w / 2 ? 1.0f : 1.5f;
      labels.at<uint16_t>(y, x) = x < w / 2 ? 5 : 9;
    }
  }
  for (int i = 0; i < 3; ++i) {
    auto stats = volume::integrate(map, depth, color, labels, confidence, k, Pose::Identity());
    if (!stats) {
      std::fprintf(stderr, "tiny map: %s\n", stats.error().c_str());
      std::abort();
    }
  }
  return map;
}

}  // namespace semfuse::fuzz
