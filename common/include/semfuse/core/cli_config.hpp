#pragma once
// YAML configuration files for CLI11 programs. Every semfuse program does
//
//   CLI::App app{"..."};
//   app.add_option("--voxel-size", voxel_size);
//   app.add_option("--volume.truncation", truncation);   // dotted name = nested YAML key
//   semfuse::addYamlConfig(app);                          // --config FILE
//   CLI11_PARSE(app, argc, argv);
//
// and reads files such as
//
//   voxel-size: 0.02
//   volume:
//     truncation: 0.08          # -> --volume.truncation
//   query:                      # a subcommand's section
//     timeout: 5                # -> `query --timeout`
//
// Flags given on the command line win over the file. A nested map is matched first against
// subcommands (as CLI11's own INI/TOML sections are) and otherwise joined with '.' into an option
// name. Unknown keys and malformed YAML are parse errors naming the key and its line.
#include <iosfwd>
#include <string>
#include <vector>

#include <CLI/App.hpp>
#include <CLI/ConfigFwd.hpp>

namespace semfuse {

class YamlConfig : public CLI::Config {
 public:
  // `app` is the application whose options the file sets; it owns this formatter, so it outlives it.
  explicit YamlConfig(const CLI::App& app) : app_(&app) {}

  // Current values (and defaults, with default_also) as nested YAML; descriptions are not written.
  std::string to_config(const CLI::App* app, bool default_also, bool write_description,
                        std::string prefix) const override;
  // Throws CLI::ConfigError (a CLI::ParseError, so CLI11_PARSE reports it and exits) on bad input.
  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override;

 private:
  const CLI::App* app_;
};

// Installs YamlConfig on `app` and adds `--config FILE` (optionally with a default file, and
// optionally required). Returns the option, e.g. to add a check or an environment variable.
CLI::Option* addYamlConfig(CLI::App& app, const std::string& default_file = "", bool required = false);

}  // namespace semfuse
