// semfuse-server: owns the labeled TSDF map and serves it over DDS (docs/architecture.md).
#include <csignal>
#include <cstdio>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "fusion_server.hpp"
#include "semfuse/core/cli_config.hpp"
#include "semfuse/core/logging.hpp"
#include "semfuse/core/malloc_tuning.hpp"
#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"

int main(int argc, char** argv) {
  semfuse::server::ServerConfig config;
  CLI::App app{
      "semfuse-server: fuses RGB-D frames and per-pixel labels from DDS clients into one labeled "
      "TSDF map (OpenVDB) and answers raycast, label, object, mesh and admin queries."};
  app.option_defaults()->always_capture_default();
  std::string log_level;
  semfuse::addYamlConfig(app);
  app.add_option("--log-level", log_level,
                 std::string("log level: ") + semfuse::logLevelNames() + " (default: $SEMFUSE_LOG_LEVEL or info)");
  bool print_config = false;
  app.add_flag("--print-config", print_config,
               "print the effective configuration (defaults, --config file, flags) as YAML that --config reads, "
               "and exit")
      ->configurable(false);
  semfuse::server::addServerOptions(app, config);
  CLI11_PARSE(app, argc, argv);
  if (print_config) {
    std::fputs(app.config_to_str(/*default_also=*/true, /*write_description=*/false).c_str(), stdout);
    return 0;
  }
  if (semfuse::Status ok = semfuse::setupLogging("semfuse-server", log_level); !ok) {
    std::fprintf(stderr, "semfuse-server: %s\n", ok.error().c_str());
    return 2;
  }
  semfuse::keepScratchResident();

  // Signals are turned into a stop request by a dedicated thread (sigwait), so shutdown runs in
  // normal code: finish queued frames, save the map.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  try {
    semfuse::server::nameTbbWorkers();  // loading and saving the map run parallel work here
    semfuse::server::FusionServer server(config);
    std::thread signal_thread([&] {
      semfuse::setCurrentThreadName("sf-signals");
      int received = 0;
      sigwait(&signals, &received);
      spdlog::info("signal {}: stopping", received);
      server.requestStop();
    });
    const int code = server.run();
    if (signal_thread.joinable()) {
      // run() can also end on its own; wake the signal thread so it can be joined.
      pthread_kill(signal_thread.native_handle(), SIGTERM);
      signal_thread.join();
    }
    return code;
  } catch (const std::exception& error) {
    spdlog::critical("{}", error.what());
    return 1;
  }
}
