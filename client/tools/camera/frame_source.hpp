#pragma once
// Where semfuse-camera's frames come from: a 7-Scenes folder, a TUM RGB-D folder or the built-in
// synthetic room, behind one indexable interface so the replay loop does not care which.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::tools {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual std::size_t count() const = 0;
  // Frame `index` in [0, count()), with its dataset's camera id and seq.
  virtual Result<Frame> load(std::size_t index) const = 0;
  virtual std::string describe() const = 0;
};

struct SyntheticSourceOptions {
  int frames = 300;
  uint64_t seed = 0;
  bool depth_noise = false;
};

// spec: "7scenes:DIR", "tum:DIR" or "synthetic". Fails with a message naming the problem.
Result<std::unique_ptr<FrameSource>> openFrameSource(const std::string& spec, const SyntheticSourceOptions& synthetic);

}  // namespace semfuse::tools
