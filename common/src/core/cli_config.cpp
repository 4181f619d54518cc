#include "semfuse/core/cli_config.hpp"

#include <istream>
#include <sstream>

#include <yaml-cpp/yaml.h>
#include <CLI/CLI.hpp>

namespace semfuse {
namespace {

std::string lineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.line < 0 ? std::string() : " (line " + std::to_string(mark.line + 1) + ")";
}

std::string join(const std::vector<std::string>& parts, std::size_t first, const char* separator) {
  std::string joined;
  for (std::size_t i = first; i < parts.size(); ++i) joined += (i > first ? separator : "") + parts[i];
  return joined;
}

const CLI::Option* findOption(const CLI::App& app, const std::string& name) {
  if (const CLI::Option* option = app.get_option_no_throw("--" + name)) return option;
  if (name.size() == 1) {
    if (const CLI::Option* option = app.get_option_no_throw("-" + name)) return option;
  }
  return app.get_option_no_throw(name);
}

std::string knownKeys(const CLI::App& app) {
  std::string keys;
  for (const CLI::Option* option : app.get_options()) {
    if (!option->get_configurable() || option->get_lnames().empty() || option == app.get_config_ptr()) continue;
    keys += (keys.empty() ? "" : ", ") + option->get_lnames().front();
  }
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    keys += (keys.empty() ? "" : ", ") + sub->get_name() + ": {...}";
  }
  return keys.empty() ? "none" : keys;
}

bool isNumeric(const CLI::Option& option) {
  const std::string type = option.get_type_name();  // e.g. "FLOAT", "UINT:POSITIVE", "[INT,INT]"
  return type.find("INT") != std::string::npos || type.find("FLOAT") != std::string::npos ||
         type.find("NUMBER") != std::string::npos;
}

// Turns one YAML leaf (a scalar or a list of scalars) at `path` into a CLI11 config item: leading
// keys that name subcommands become parents, the rest is joined with '.' into the option name.
CLI::ConfigItem makeItem(const CLI::App& root, const std::vector<std::string>& path, const YAML::Node& value) {
  const CLI::App* app = &root;
  CLI::ConfigItem item;
  std::size_t i = 0;
  for (; i + 1 < path.size(); ++i) {
    const CLI::App* sub = nullptr;
    for (const CLI::App* candidate : app->get_subcommands([](const CLI::App*) { return true; })) {
      if (candidate->check_name(path[i])) sub = candidate;
    }
    if (sub == nullptr) break;
    item.parents.push_back(sub->get_name());
    app = sub;
  }
  item.name = join(path, i, ".");
  const CLI::Option* option = findOption(*app, item.name);
  if (option == nullptr) {
    throw CLI::ConfigError("config: unknown key '" + join(path, 0, ".") + "'" + lineOf(value) + "; known keys" +
                           (app == &root ? "" : " of '" + app->get_name() + "'") + ": " + knownKeys(*app));
  }
  if (value.IsScalar()) {
    // CLI11 converts an empty string to a number as 0: `voxel-size: ""` (or a tag with no value)
    // would set a size of zero behind the options' own checks.
    if (value.Scalar().empty() && isNumeric(*option)) {
      throw CLI::ConfigError("config: '" + join(path, 0, ".") + "'" + lineOf(value) + " has an empty value");
    }
    item.inputs.push_back(value.Scalar());
  } else if (value.IsSequence()) {
    for (const YAML::Node& element : value) {
      if (!element.IsScalar()) {
        throw CLI::ConfigError("config: '" + join(path, 0, ".") + "'" + lineOf(element) +
                               ": list elements must be plain values");
      }
      item.inputs.push_back(element.Scalar());
    }
  } else {
    throw CLI::ConfigError("config: '" + join(path, 0, ".") + "'" + lineOf(value) + " has no value");
  }
  return item;
}

void collect(const CLI::App& root, const YAML::Node& map, std::vector<std::string>& path,
             std::vector<CLI::ConfigItem>& items) {
  for (const auto& entry : map) {
    if (!entry.first.IsScalar()) throw CLI::ConfigError("config: keys must be plain names" + lineOf(entry.first));
    path.push_back(entry.first.Scalar());
    if (entry.second.IsMap()) {
      collect(root, entry.second, path, items);
    } else {
      items.push_back(makeItem(root, path, entry.second));
    }
    path.pop_back();
  }
}

// Sets root[a][b][c] = value for a dotted name "a.b.c".
void setNested(YAML::Node root, const std::string& dotted, const YAML::Node& value) {
  std::vector<std::string> keys;
  std::stringstream split(dotted);
  for (std::string key; std::getline(split, key, '.');) keys.push_back(key);
  // yaml-cpp nodes are handles: walking with operator[] and reset() keeps the edits in the tree.
  YAML::Node node = root;
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    YAML::Node child = node[keys[i]];
    node.reset(child);
  }
  node[keys.back()] = value;
}

// A name that is also a section (--esdf beside --esdf.max-distance) is written by a dotted alias
// (--esdf.enabled), which the section's YAML map can hold beside its other keys.
const std::string& yamlName(const CLI::Option& option) {
  for (const std::string& name : option.get_lnames())
    if (name.find('.') != std::string::npos) return name;
  return option.get_lnames().front();
}

YAML::Node appToYaml(const CLI::App& app, bool default_also) {
  YAML::Node node(YAML::NodeType::Map);
  for (const CLI::Option* option : app.get_options()) {
    if (!option->get_configurable() || option->get_lnames().empty() || option == app.get_config_ptr()) continue;
    std::vector<std::string> values = option->results();
    // CLI11 shows an empty list default as "[]": written as a value it would read back as the
    // one-element list "[]" and fail to convert, so an empty default is left out like no default.
    const std::string default_str = option->get_default_str();
    if (values.empty() && default_also && !default_str.empty() && default_str != "[]") {
      values.push_back(default_str);
    }
    if (values.empty()) continue;
    YAML::Node value;
    if (values.size() == 1) {
      value = values.front();
    } else {
      for (const std::string& v : values) value.push_back(v);
    }
    setNested(node, yamlName(*option), value);
  }
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    YAML::Node child = appToYaml(*sub, default_also);
    if (child.size() > 0) node[sub->get_name()] = child;
  }
  return node;
}

}  // namespace

std::vector<CLI::ConfigItem> YamlConfig::from_config(std::istream& input) const {
  YAML::Node document;
  try {
    document = YAML::Load(input);
  } catch (const YAML::Exception& e) {
    throw CLI::ConfigError("config: malformed YAML at line " + std::to_string(e.mark.line + 1) + ", column " +
                           std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  std::vector<CLI::ConfigItem> items;
  if (document.IsNull()) return items;  // an empty file configures nothing
  if (!document.IsMap()) throw CLI::ConfigError("config: the top level of a config file must be a map of keys");
  std::vector<std::string> path;
  collect(*app_, document, path, items);
  return items;
}

std::string YamlConfig::to_config(const CLI::App* app, bool default_also, bool /*write_description*/,
                                  std::string /*prefix*/) const {
  YAML::Emitter out;
  out << appToYaml(app != nullptr ? *app : *app_, default_also);
  return std::string(out.c_str()) + "\n";
}

CLI::Option* addYamlConfig(CLI::App& app, const std::string& default_file, bool required) {
  app.config_formatter(std::make_shared<YamlConfig>(app));
  // Unknown keys are rejected in YamlConfig::from_config already; this catches anything else.
  app.allow_config_extras(CLI::config_extras_mode::error);
  return app.set_config("--config", default_file, "YAML config file; command-line flags override its values", required);
}

}  // namespace semfuse
