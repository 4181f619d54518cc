#include "track/track_sequence.hpp"

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>

#include <tbb/parallel_for.h>

#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/datasets/tum_rgbd.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/tracking/se3.hpp"

namespace semfuse::bench {
namespace {

// Loads frames 0..count-1 with `load(i)` on all cores; the first error wins.
template <typename Load>
Status loadAll(std::size_t count, std::vector<Frame>& frames, Load&& load) {
  frames.resize(count);
  std::mutex error_mutex;
  std::string error;
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    Result<Frame> frame = load(i);
    if (!frame) {
      std::lock_guard lock(error_mutex);
      if (error.empty()) error = "frame " + std::to_string(i) + ": " + frame.error();
      return;
    }
    frames[i] = std::move(frame).value();
  });
  if (!error.empty()) return makeError(error);
  return Status::Ok();
}

// Moves each frame's pose into `references` (orthonormalised: 7-Scenes' text matrices are only
// approximately rigid) and leaves the frame without one. The first frame must have one: it places
// the tracked trajectory in the reference's frame.
Status takeReferences(std::vector<Frame>& frames, std::vector<std::optional<Pose>>& references) {
  references.resize(frames.size());
  if (frames.empty() || !frames.front().camera_to_world) return makeError("the first frame has no reference pose");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].camera_to_world) references[i] = tracking::orthonormalized(*frames[i].camera_to_world);
    frames[i].camera_to_world.reset();
  }
  return Status::Ok();
}

std::size_t limit(std::size_t available, std::size_t max_frames) {
  return max_frames == 0 ? available : std::min(available, max_frames);
}

}  // namespace

Result<TrackSequence> TrackSequence::load(const std::string& spec, std::size_t max_frames) {
  TrackSequence sequence;
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string argument = colon == std::string::npos ? std::string() : spec.substr(colon + 1);
  Status loaded = Status::Ok();
  if (kind == "tum") {
    auto reader = datasets::TumRgbdReader::open(argument);
    if (!reader) return makeError(reader.error());
    const datasets::TumRgbdReader& r = reader.value();
    // From the first frame with ground truth to the last (a frame in a gap of the motion capture
    // is played but not judged).
    std::size_t first = 0, end = r.count();
    while (first < end && !r.entry(first).camera_to_world) ++first;
    while (end > first && !r.entry(end - 1).camera_to_world) --end;
    const std::size_t count = limit(end - first, max_frames);
    if (count == 0) return makeError("TUM folder " + argument + " has no frame with ground truth");
    loaded = loadAll(count, sequence.frames_, [&](std::size_t i) { return r.load(first + i); });
    sequence.name_ = "TUM " + std::filesystem::path(argument).filename().string();
    if (sequence.name_ == "TUM ")
      sequence.name_ = "TUM " + std::filesystem::path(argument).parent_path().filename().string();
    sequence.reference_kind_ = "motion capture";
    sequence.reference_is_truth_ = true;
  } else if (kind == "7scenes") {
    auto reader = datasets::SevenScenesReader::open(argument);
    if (!reader) return makeError(reader.error());
    const datasets::SevenScenesReader& r = reader.value();
    const std::size_t count = limit(r.count(), max_frames);
    loaded = loadAll(count, sequence.frames_, [&](std::size_t i) { return r.load(i); });
    sequence.name_ = "7-Scenes " + std::filesystem::path(argument).filename().string();
    if (sequence.name_ == "7-Scenes ")
      sequence.name_ = "7-Scenes " + std::filesystem::path(argument).parent_path().filename().string();
    sequence.reference_kind_ = "KinectFusion reconstruction";
    sequence.reference_is_truth_ = false;
    sequence.color_registered_ = false;
  } else if (kind == "synthetic") {
    synthetic::SequenceConfig config;
    if (!argument.empty()) {
      try {
        config.trajectory.frame_count = std::stoi(argument);
      } catch (const std::exception&) {
        return makeError("synthetic:N needs a frame count, got '" + argument + "'");
      }
    }
    if (config.trajectory.frame_count < 2) return makeError("synthetic:N needs at least 2 frames");
    const synthetic::SyntheticSequence synthetic(config);
    const std::size_t count = limit(static_cast<std::size_t>(synthetic.frameCount()), max_frames);
    loaded = loadAll(count, sequence.frames_, [&](std::size_t i) { return synthetic.frame(static_cast<int>(i)); });
    sequence.name_ = "synthetic room";
    sequence.reference_kind_ = "exact";
    sequence.reference_is_truth_ = true;
  } else {
    return makeError("sequence '" + spec + "': expected tum:DIR, 7scenes:DIR or synthetic[:N]");
  }
  if (!loaded) return makeError(spec + ": " + loaded.error());
  if (Status status = takeReferences(sequence.frames_, sequence.references_); !status)
    return makeError(spec + ": " + status.error());
  return sequence;
}

}  // namespace semfuse::bench
