#include "frame_source.hpp"

#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/datasets/tum_rgbd.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"

namespace semfuse::tools {
namespace {

class SevenScenesSource : public FrameSource {
 public:
  explicit SevenScenesSource(datasets::SevenScenesReader reader) : reader_(std::move(reader)) {}
  std::size_t count() const override { return reader_.count(); }
  Result<Frame> load(std::size_t index) const override { return reader_.load(index); }
  std::string describe() const override { return "7-Scenes folder " + reader_.folder().string(); }

 private:
  datasets::SevenScenesReader reader_;
};

class TumSource : public FrameSource {
 public:
  TumSource(datasets::TumRgbdReader reader, std::string folder)
      : reader_(std::move(reader)), folder_(std::move(folder)) {}
  std::size_t count() const override { return reader_.count(); }
  Result<Frame> load(std::size_t index) const override { return reader_.load(index); }
  std::string describe() const override { return "TUM RGB-D folder " + folder_; }

 private:
  datasets::TumRgbdReader reader_;
  std::string folder_;
};

class SyntheticSource : public FrameSource {
 public:
  explicit SyntheticSource(synthetic::SequenceConfig config) : sequence_(std::move(config)) {}
  std::size_t count() const override { return static_cast<std::size_t>(sequence_.frameCount()); }
  Result<Frame> load(std::size_t index) const override { return sequence_.frame(static_cast<int>(index)); }
  std::string describe() const override {
    return "synthetic room, " + std::to_string(sequence_.frameCount()) + " frames";
  }

 private:
  synthetic::SyntheticSequence sequence_;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> openFrameSource(const std::string& spec, const SyntheticSourceOptions& synthetic) {
  if (spec == "synthetic") {
    if (synthetic.frames < 1) return makeError("--frames must be at least 1");
    synthetic::SequenceConfig config;
    config.trajectory.frame_count = synthetic.frames;
    config.room.seed = synthetic.seed;
    config.seed = synthetic.seed;
    if (synthetic.depth_noise) config.noise = synthetic::DepthNoiseParams{};
    return std::unique_ptr<FrameSource>(std::make_unique<SyntheticSource>(config));
  }
  const auto colon = spec.find(':');
  if (colon == std::string::npos || colon + 1 == spec.size()) {
    return makeError("--source must be 7scenes:DIR, tum:DIR or synthetic, not '" + spec + "'");
  }
  const std::string kind = spec.substr(0, colon);
  const std::string folder = spec.substr(colon + 1);
  if (kind == "7scenes") {
    auto reader = datasets::SevenScenesReader::open(folder);
    if (!reader) return makeError(reader.error());
    return std::unique_ptr<FrameSource>(std::make_unique<SevenScenesSource>(std::move(reader).value()));
  }
  if (kind == "tum") {
    auto reader = datasets::TumRgbdReader::open(folder);
    if (!reader) return makeError(reader.error());
    return std::unique_ptr<FrameSource>(std::make_unique<TumSource>(std::move(reader).value(), folder));
  }
  return makeError("unknown source kind '" + kind + "' (7scenes, tum, synthetic)");
}

}  // namespace semfuse::tools
