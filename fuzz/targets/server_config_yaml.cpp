// Fuzz target: semfuse-server's YAML config file (--config FILE): the server's own options
// (server/core/src/server_config.cpp) on a CLI11 app with semfuse::YamlConfig, parsed as the
// server parses it. Malformed input must end as a CLI11 parse error, never anything else.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "fuzz_support.hpp"
#include "semfuse/core/cli_config.hpp"
#include "server_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  semfuse::server::ServerConfig config;
  CLI::App app{"fuzzed semfuse-server"};
  app.option_defaults()->always_capture_default();
  semfuse::addYamlConfig(app);
  std::string log_level;
  app.add_option("--log-level", log_level);
  semfuse::server::addServerOptions(app, config);
  const auto path =
      semfuse::fuzz::writeScratchFile("server.yaml", std::string_view(reinterpret_cast<const char*>(data), size));
  const std::string config_arg = path.string();
  const char* argv[] = {"semfuse-server", "--config", config_arg.c_str()};
  try {
    app.parse(3, argv);
  } catch (const CLI::ParseError&) {
    return 0;  // what CLI11_PARSE turns into a message and exit code 2
  }
  // Accepted: the options' own checks held.
  SEMFUSE_FUZZ_CHECK(config.volume.voxel_size > 0.0 && config.volume.truncation > 0.0 && config.queue_per_camera > 0);
  // What was read writes back out as YAML that reads in again.
  const std::string written = app.config_to_str(true, false);
  semfuse::server::ServerConfig again;
  CLI::App reread{"fuzzed semfuse-server, second read"};
  semfuse::addYamlConfig(reread);
  reread.add_option("--log-level", log_level);
  semfuse::server::addServerOptions(reread, again);
  const auto second = semfuse::fuzz::writeScratchFile("server-again.yaml", written);
  const std::string second_arg = second.string();
  const char* argv2[] = {"semfuse-server", "--config", second_arg.c_str()};
  try {
    reread.parse(3, argv2);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "written config does not read back: %s\n%s\n", e.what(), written.c_str());
    SEMFUSE_FUZZ_CHECK(false);
  }
  return 0;
}
