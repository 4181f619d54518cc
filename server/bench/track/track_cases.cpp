#include "track/track_cases.hpp"

#include <cmath>
#include <random>
#include <sstream>

#include <Eigen/Core>

namespace semfuse::bench {
namespace {

Result<std::size_t> parseIndex(const std::string& text, const std::string& spec) {
  try {
    std::size_t used = 0;
    const unsigned long value = std::stoul(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return static_cast<std::size_t>(value);
  } catch (const std::exception&) {
    return makeError("case '" + spec + "': '" + text + "' is not a frame number");
  }
}

// "S+N" -> [S, S+N)
Result<std::pair<std::size_t, std::size_t>> parseSpan(const std::string& text, const std::string& spec,
                                                      std::size_t size) {
  const auto plus = text.find('+');
  if (plus == std::string::npos) return makeError("case '" + spec + "': expected START+COUNT");
  auto start = parseIndex(text.substr(0, plus), spec);
  auto count = parseIndex(text.substr(plus + 1), spec);
  if (!start) return makeError(start.error());
  if (!count) return makeError(count.error());
  if (count.value() == 0 || start.value() + count.value() > size)
    return makeError("case '" + spec + "': frames " + text + " are not within the sequence's " + std::to_string(size) +
                     " frames");
  return std::make_pair(start.value(), start.value() + count.value());
}

// Keeps the pixels on the plane with the most support (RANSAC over a grid of back-projected
// points, 1.5 cm band); everything else becomes invalid.
cv::Mat dominantPlaneOnly(const cv::Mat& depth, const PinholeIntrinsics& k, uint64_t seed) {
  auto point = [&](int u, int v) {
    const float z = depth.at<float>(v, u);
    return Eigen::Vector3f((static_cast<float>(u) - static_cast<float>(k.cx)) * z / static_cast<float>(k.fx),
                           (static_cast<float>(v) - static_cast<float>(k.cy)) * z / static_cast<float>(k.fy), z);
  };
  std::vector<Eigen::Vector3f> samples;
  for (int v = 0; v < depth.rows; v += 8)
    for (int u = 0; u < depth.cols; u += 8)
      if (depth.at<float>(v, u) > 0.0f) samples.push_back(point(u, v));
  cv::Mat out(depth.size(), CV_32FC1, cv::Scalar(0.0f));
  if (samples.size() < 3) return out;
  constexpr float kBand = 0.015f;
  std::mt19937 rng(static_cast<uint32_t>(seed));
  std::uniform_int_distribution<std::size_t> pick(0, samples.size() - 1);
  Eigen::Vector3f best_normal = Eigen::Vector3f::UnitZ();
  float best_offset = 0.0f;
  std::size_t best_support = 0;
  for (int attempt = 0; attempt < 300; ++attempt) {
    const Eigen::Vector3f a = samples[pick(rng)], b = samples[pick(rng)], c = samples[pick(rng)];
    Eigen::Vector3f normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-6f) continue;
    normal.normalize();
    const float offset = normal.dot(a);
    std::size_t support = 0;
    for (const auto& p : samples) support += std::abs(normal.dot(p) - offset) < kBand;
    if (support > best_support) {
      best_support = support;
      best_normal = normal;
      best_offset = offset;
    }
  }
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u)
      if (depth.at<float>(v, u) > 0.0f && std::abs(best_normal.dot(point(u, v)) - best_offset) < kBand)
        out.at<float>(v, u) = depth.at<float>(v, u);
  return out;
}

}  // namespace

Result<TrackCase> makeTrackCase(const std::string& spec, std::size_t size) {
  TrackCase out;
  out.spec = spec;
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string argument = colon == std::string::npos ? std::string() : spec.substr(colon + 1);
  auto all = [&](FrameAlteration alteration, std::size_t from, std::size_t to) {
    for (std::size_t i = 0; i < size; ++i)
      out.steps.push_back({i, i >= from && i < to ? alteration : FrameAlteration::kNone});
  };
  if (kind == "full") {
    all(FrameAlteration::kNone, 0, 0);
  } else if (kind == "stride") {
    auto stride = parseIndex(argument, spec);
    if (!stride) return makeError(stride.error());
    if (stride.value() < 1) return makeError("case '" + spec + "': stride must be >= 1");
    for (std::size_t i = 0; i < size; i += stride.value()) out.steps.push_back({i, FrameAlteration::kNone});
  } else if (kind == "jump") {
    std::stringstream segments(argument);
    std::string segment;
    while (std::getline(segments, segment, ',')) {
      const auto dash = segment.find('-');
      if (dash == std::string::npos) return makeError("case '" + spec + "': segment '" + segment + "' is not A-B");
      auto from = parseIndex(segment.substr(0, dash), spec);
      auto to = parseIndex(segment.substr(dash + 1), spec);
      if (!from) return makeError(from.error());
      if (!to) return makeError(to.error());
      if (from.value() > to.value() || to.value() >= size)
        return makeError("case '" + spec + "': segment " + segment + " is not within 0-" + std::to_string(size - 1));
      if (!out.steps.empty()) out.resumptions.push_back(out.steps.size());
      for (std::size_t i = from.value(); i <= to.value(); ++i) out.steps.push_back({i, FrameAlteration::kNone});
    }
    if (out.steps.empty()) return makeError("case '" + spec + "': no segment");
  } else if (kind == "covered" || kind == "plane") {
    auto span = parseSpan(argument, spec, size);
    if (!span) return makeError(span.error());
    const auto [from, to] = span.value();
    all(kind == "covered" ? FrameAlteration::kCovered : FrameAlteration::kOnePlane, from, to);
    if (kind == "covered" && to < size) out.resumptions.push_back(to);
  } else {
    return makeError("case '" + spec + "': expected full, stride:K, jump:A-B,C-D, covered:S+N or plane:S+N");
  }
  if (out.steps.size() < 2) return makeError("case '" + spec + "' plays fewer than 2 frames");
  return out;
}

Frame alterFrame(const Frame& frame, FrameAlteration alteration) {
  Frame out = frame;  // shallow: the images are shared until replaced
  switch (alteration) {
    case FrameAlteration::kNone:
      break;
    case FrameAlteration::kCovered:
      out.depth = cv::Mat(frame.depth.size(), frame.depth.type(), cv::Scalar(0));
      if (!frame.color.empty()) out.color = cv::Mat(frame.color.size(), frame.color.type(), cv::Scalar(0, 0, 0));
      break;
    case FrameAlteration::kOnePlane:
      out.depth = dominantPlaneOnly(frame.depth, frame.intrinsics, frame.seq);
      break;
  }
  return out;
}

}  // namespace semfuse::bench
