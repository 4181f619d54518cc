#pragma once
// Self-registration of semfuse-bench subcommands. A bench file declares, at namespace scope, a
// constant named after it (unity builds compile several bench files in one unit):
//
//   const bool render_registered = semfuse::bench::registerBench("render", "raycast and mesh timings",
//       [](CLI::App& command) {
//         auto options = std::make_shared<RenderOptions>();
//         command.add_option("--frames", options->frames, "frames to render");
//         return [options] { return runRenderBench(*options); };  // exit code
//       });
//
// main() creates one CLI11 subcommand per registration, lets the setup declare its options, and
// runs the chosen one after parsing.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace semfuse::bench {

using BenchRun = std::function<int()>;                  // runs the benchmark, returns the exit code
using BenchSetup = std::function<BenchRun(CLI::App&)>;  // declares options, returns the run

struct BenchRegistration {
  std::string name;
  std::string description;
  BenchSetup setup;
};

// Always returns true, so that it can initialise a namespace-scope constant.
bool registerBench(std::string name, std::string description, BenchSetup setup);
const std::vector<BenchRegistration>& registeredBenches();

// The options of every bench that fuses a 7-Scenes sequence into a map: --data (the sequence's
// folder), --voxel and --trunc (metres; what 0 means, if anything, in `truncation_note`).
void addMapOptions(CLI::App& command, std::string& data, double& voxel, double& truncation,
                   const std::string& truncation_note = {});

}  // namespace semfuse::bench
