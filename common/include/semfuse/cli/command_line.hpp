#pragma once
// Command line handling the semfuse client programs and semfuse-eval do the same way: bad usage
// prints the error and the help text on stderr and exits 2 (CLI11's own default exit code for
// parse errors is 106 and varies by error, which scripts cannot rely on).
#include <CLI/App.hpp>

namespace semfuse::cli {

// Parses argv. Returns -1 to go on; otherwise the exit code the program must return now
// (0 after --help/--version, 2 after a usage error).
int parseCommandLine(CLI::App& app, int argc, char** argv);

// Adds --log-level, --domain-id and --dds-profile (the options every program has).
// --dds-profile sets CYCLONEDDS_URI while the command line is parsed, that is before the
// program creates its participant (Cyclone reads the variable only then).
struct CommonOptions {
  std::string log_level;
  int domain_id = -1;       // -1 = Cyclone's default domain (CYCLONEDDS_URI or 0)
  std::string dds_profile;  // Cyclone XML file; empty = $CYCLONEDDS_URI or Cyclone's defaults
};
void addCommonOptions(CLI::App& app, CommonOptions& options);

}  // namespace semfuse::cli
