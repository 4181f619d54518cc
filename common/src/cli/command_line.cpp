#include "semfuse/cli/command_line.hpp"

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "semfuse/cli/exit_codes.hpp"
#include "semfuse/core/logging.hpp"

namespace semfuse::cli {

int parseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    std::cout << app.version() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    // Help of the subcommand the user was typing, when there is one.
    const CLI::App* context = &app;
    for (const CLI::App* sub : app.get_subcommands()) context = sub;
    std::cerr << "error: " << e.what() << "\n\n" << context->help();
    return kExitUsage;
  }
  return -1;
}

void addCommonOptions(CLI::App& app, CommonOptions& options) {
  app.add_option("--log-level", options.log_level,
                 std::string("log level: ") + logLevelNames() + " (default: $SEMFUSE_LOG_LEVEL or info)");
  app.add_option("--domain-id", options.domain_id, "DDS domain id (default: Cyclone's default domain)")
      ->check(CLI::Range(-1, 232));
  app.add_option("--dds-profile", options.dds_profile,
                 "Cyclone DDS XML profile, e.g. deploy/dds/lan.xml (default: $CYCLONEDDS_URI)")
      ->check(CLI::ExistingFile)
      ->each([](const std::string& path) {
        const std::string uri = "file://" + std::filesystem::absolute(path).string();
        ::setenv("CYCLONEDDS_URI", uri.c_str(), 1);
      });
}

}  // namespace semfuse::cli
