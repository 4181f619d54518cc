#include "semfuse/core/legend_io.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace semfuse {
namespace {

std::string where(const std::string& source, const YAML::Node& node) {
  if (!node.IsDefined()) return source;  // a missing key: Mark() would throw YAML::InvalidNode
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return source;
  return source + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

// An integer scalar within [low, high]; yaml-cpp's as<int> would accept "1.5" as 1 on some versions.
Result<long long> integerIn(const YAML::Node& node, long long low, long long high, const std::string& what,
                            const std::string& source) {
  if (!node || !node.IsScalar()) return makeError(where(source, node) + ": " + what + " must be an integer");
  const std::string& text = node.Scalar();
  long long value = 0;
  std::istringstream parse(text);
  if (!(parse >> value) || !parse.eof()) {
    return makeError(where(source, node) + ": " + what + " '" + text + "' is not an integer");
  }
  if (value < low || value > high) {
    return makeError(where(source, node) + ": " + what + " " + text + " outside [" + std::to_string(low) + ", " +
                     std::to_string(high) + "]");
  }
  return value;
}

// The length of the well-formed UTF-8 sequence starting at `at`, or 0. Well-formed means RFC 3629:
// no overlong forms (C1 8F is 'O' written in two bytes), no UTF-16 surrogates, nothing past
// U+10FFFF. yaml-cpp's emitter rewrites such sequences, so a legend holding one would not read
// back as written.
std::size_t utf8SequenceLength(const std::string& text, std::size_t at) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[at + k]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  const std::size_t length = (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xe ? 3 : (lead >> 3) == 0x1e ? 4 : 0;
  if (length == 0 || at + length > text.size()) return 0;
  uint32_t code_point = lead & (0x7f >> length);
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(k) & 0xc0) != 0x80) return 0;
    code_point = (code_point << 6) | (byte(k) & 0x3f);
  }
  constexpr uint32_t kSmallestOfLength[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (code_point < kSmallestOfLength[length]) return 0;        // overlong
  if (code_point >= 0xd800 && code_point <= 0xdfff) return 0;  // surrogate
  if (code_point > 0x10ffff) return 0;                         // past Unicode
  return length;
}

// Names travel as DDS strings (UTF-8 for ROS 2), one per line in map files and through YAML,
// so they must be well-formed UTF-8 without control characters (a newline would break the map
// file's legend, malformed UTF-8 does not survive a YAML round trip).
std::string nameProblem(const std::string& name) {
  for (std::size_t i = 0; i < name.size();) {
    const auto byte = static_cast<unsigned char>(name[i]);
    if (byte < 0x20 || byte == 0x7f) return "has a control character at byte " + std::to_string(i);
    const std::size_t length = utf8SequenceLength(name, i);
    if (length == 0) return "is not valid UTF-8 at byte " + std::to_string(i);
    i += length;
  }
  return "";
}

}  // namespace

Status validateLegend(const LabelLegend& legend) {
  if (std::string problem = nameProblem(legend.name); !problem.empty()) return makeError("legend name " + problem);
  if (legend.labels.empty()) return makeError("legend '" + legend.name + "' has no labels");
  std::set<std::string> names;
  for (std::size_t i = 0; i < legend.labels.size(); ++i) {
    const LabelInfo& label = legend.labels[i];
    if (i > 0 && label.id <= legend.labels[i - 1].id) {
      return makeError(
          "legend '" + legend.name + "': label id " + std::to_string(label.id) +
          (label.id == legend.labels[i - 1].id ? " appears twice" : " is out of order (ids must be sorted)"));
    }
    if (label.name.empty())
      return makeError("legend '" + legend.name + "': label " + std::to_string(label.id) + " has no name");
    if (std::string problem = nameProblem(label.name); !problem.empty()) {
      return makeError("legend '" + legend.name + "': the name of label " + std::to_string(label.id) + " " + problem);
    }
    if (!names.insert(label.name).second) {
      return makeError("legend '" + legend.name + "': name '" + label.name + "' used by two labels");
    }
  }
  for (std::size_t i = 0; i < legend.background_ids.size(); ++i) {
    const LabelId id = legend.background_ids[i];
    if (!legend.contains(id)) {
      return makeError("legend '" + legend.name + "': background id " + std::to_string(id) + " is not a label");
    }
    if (i > 0 && id <= legend.background_ids[i - 1]) {
      return makeError("legend '" + legend.name + "': background ids must be sorted and unique");
    }
  }
  return Status::Ok();
}

Result<LabelLegend> parseLegendYaml(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return makeError(source + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": malformed YAML: " + e.msg);
  }
  if (!root.IsMap()) return makeError(source + ": a legend must be a map with 'name' and 'labels'");
  for (const auto& entry : root) {
    // as<std::string>() throws on a key that is a list or a map; that is an error in the file.
    if (!entry.first.IsScalar()) return makeError(where(source, entry.first) + ": keys must be plain names");
    const std::string key = entry.first.Scalar();
    if (key != "name" && key != "labels" && key != "background") {
      return makeError(where(source, entry.first) + ": unknown key '" + key + "' (known: name, labels, background)");
    }
  }

  LabelLegend legend;
  legend.name = root["name"] && root["name"].IsScalar() ? root["name"].Scalar() : "";
  if (legend.name.empty()) return makeError(source + ": legend needs a 'name'");
  const YAML::Node labels = root["labels"];
  if (!labels || !labels.IsSequence() || labels.size() == 0) {
    return makeError(source + ": legend needs a non-empty 'labels' list");
  }
  for (const YAML::Node& item : labels) {
    if (!item.IsMap()) return makeError(where(source, item) + ": each label must be a map {id, name, color}");
    for (const auto& entry : item) {
      if (!entry.first.IsScalar()) return makeError(where(source, entry.first) + ": label keys must be plain names");
      const std::string key = entry.first.Scalar();
      if (key != "id" && key != "name" && key != "color") {
        return makeError(where(source, entry.first) + ": unknown label key '" + key + "' (known: id, name, color)");
      }
    }
    auto id = integerIn(item["id"], 0, std::numeric_limits<LabelId>::max(), "label id", source);
    if (!id) return makeError(id.error());
    LabelInfo info;
    info.id = static_cast<LabelId>(id.value());
    if (!item["name"] || !item["name"].IsScalar() || item["name"].Scalar().empty()) {
      return makeError(where(source, item) + ": label " + std::to_string(info.id) + " needs a 'name'");
    }
    info.name = item["name"].Scalar();
    const YAML::Node color = item["color"];
    if (color) {
      if (!color.IsSequence() || color.size() != 3) {
        return makeError(where(source, color) + ": color of label " + std::to_string(info.id) + " must be [r, g, b]");
      }
      for (std::size_t c = 0; c < 3; ++c) {
        auto channel = integerIn(color[c], 0, 255, "colour channel", source);
        if (!channel) return makeError(channel.error());
        info.rgb[c] = static_cast<uint8_t>(channel.value());
      }
    } else {
      info.rgb = LabelLegend{}.colorOf(info.id);  // no colour given: the stable fallback colour
    }
    legend.labels.push_back(std::move(info));
  }
  std::stable_sort(legend.labels.begin(), legend.labels.end(),
                   [](const LabelInfo& a, const LabelInfo& b) { return a.id < b.id; });

  if (const YAML::Node background = root["background"]) {
    if (!background.IsSequence()) return makeError(where(source, background) + ": 'background' must be a list of ids");
    for (const YAML::Node& item : background) {
      auto id = integerIn(item, 0, std::numeric_limits<LabelId>::max(), "background id", source);
      if (!id) return makeError(id.error());
      legend.background_ids.push_back(static_cast<LabelId>(id.value()));
    }
    std::sort(legend.background_ids.begin(), legend.background_ids.end());
    legend.background_ids.erase(std::unique(legend.background_ids.begin(), legend.background_ids.end()),
                                legend.background_ids.end());
  }
  if (Status valid = validateLegend(legend); !valid) return makeError(source + ": " + valid.error());
  return legend;
}

Result<LabelLegend> loadLegendYaml(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return makeError("legend file missing or unreadable: " + file.string());
  std::ostringstream text;
  text << in.rdbuf();
  return parseLegendYaml(text.str(), file.string());
}

Result<LabelLegend> resolveLegend(const std::string& name_or_file) {
  if (auto legend = builtinLegend(name_or_file)) return *legend;
  std::error_code ec;
  if (!std::filesystem::exists(name_or_file, ec)) {
    std::string names;
    for (const std::string& name : builtinLegendNames()) names += (names.empty() ? "" : ", ") + name;
    return makeError("legend '" + name_or_file + "' is neither a built-in legend (" + names + ") nor a file");
  }
  return loadLegendYaml(name_or_file);
}

std::string legendToYaml(const LabelLegend& legend) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << legend.name;
  out << YAML::Key << "labels" << YAML::Value << YAML::BeginSeq;
  for (const LabelInfo& label : legend.labels) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << label.id << YAML::Key << "name"
        << YAML::Value << label.name << YAML::Key << "color" << YAML::Value << YAML::Flow << YAML::BeginSeq
        << static_cast<int>(label.rgb[0]) << static_cast<int>(label.rgb[1]) << static_cast<int>(label.rgb[2])
        << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "background" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (LabelId id : legend.background_ids) out << id;
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace semfuse
