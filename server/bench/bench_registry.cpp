#include "bench_registry.hpp"

#include <utility>

namespace semfuse::bench {
namespace {
// A function-local static: registrations run during static initialisation of other files, in an
// order the language does not define, so the list must exist before its first use.
std::vector<BenchRegistration>& registry() {
  static std::vector<BenchRegistration> benches;
  return benches;
}
}  // namespace

bool registerBench(std::string name, std::string description, BenchSetup setup) {
  registry().push_back({std::move(name), std::move(description), std::move(setup)});
  return true;
}

const std::vector<BenchRegistration>& registeredBenches() { return registry(); }

void addMapOptions(CLI::App& command, std::string& data, double& voxel, double& truncation,
                   const std::string& truncation_note) {
  command.add_option("--data", data, "7-Scenes sequence folder")->capture_default_str();
  command.add_option("--voxel", voxel, "voxel size, metres")->capture_default_str();
  command
      .add_option("--trunc", truncation,
                  "truncation, metres" + (truncation_note.empty() ? std::string() : " (" + truncation_note + ")"))
      ->capture_default_str();
}

}  // namespace semfuse::bench
