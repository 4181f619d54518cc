// semfuse-bench: speed and memory figures of the server libraries on real data. Not a test:
// prints tables to compare against the targets of the issues and against other systems.
#include <algorithm>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "bench_registry.hpp"

int main(int argc, char** argv) {
  using semfuse::bench::BenchRun;
  CLI::App app{"semfuse-bench: timings and memory of semfuse's server libraries on real data"};
  app.require_subcommand(1);

  // Sorted by name, for a stable --help whatever the link order of the bench files.
  auto benches = semfuse::bench::registeredBenches();
  std::sort(benches.begin(), benches.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::map<const CLI::App*, BenchRun> runs;
  for (const auto& bench : benches) {
    CLI::App* command = app.add_subcommand(bench.name, bench.description);
    runs[command] = bench.setup(*command);
  }
  CLI11_PARSE(app, argc, argv);
  for (const auto& [command, run] : runs)
    if (command->parsed()) return run();
  return 1;
}
