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

}  // namespace semfuse::bench
