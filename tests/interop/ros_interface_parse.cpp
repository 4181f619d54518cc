#include "ros_interface_parse.hpp"

#include <regex>
#include <sstream>
#include <stdexcept>

namespace semfuse::interop {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// Removes // comments and preprocessor lines; IDL comments never contain braces we need.
std::string stripIdlComments(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) {
    const auto c = line.find("//");
    if (c != std::string::npos) line.erase(c);
    if (trim(line).rfind('#', 0) == 0) continue;
    out += line + "\n";
  }
  return out;
}

// One IDL member ("sequence<uint8> depth", "double camera_to_world[12]") in canonical form.
Field idlMember(const std::string& decl) {
  static const std::regex re(R"(^(.+?)\s+(\w+)\s*(\[\s*(\d+)\s*\])?$)");
  std::smatch m;
  const std::string d = trim(decl);
  if (!std::regex_match(d, m, re)) throw std::runtime_error("unreadable IDL member: '" + d + "'");
  std::string type = std::regex_replace(trim(m[1].str()), std::regex(R"(\s+)"), "");
  if (m[3].matched) type += "[" + m[4].str() + "]";
  return {type, m[2].str()};
}

const std::map<std::string, std::string>& primitiveMap() {
  // rosidl primitive -> the IDL spelling rosidl_generator_dds_idl emits (and idl/ uses).
  static const std::map<std::string, std::string> map = {
      {"bool", "boolean"},  {"byte", "octet"},  {"char", "uint8"},    {"float32", "float"}, {"float64", "double"},
      {"int8", "int8"},     {"uint8", "uint8"}, {"int16", "int16"},   {"uint16", "uint16"}, {"int32", "int32"},
      {"uint32", "uint32"}, {"int64", "int64"}, {"uint64", "uint64"}, {"string", "string"}};
  return map;
}

void parseMsgSection(const std::string& text, const std::string& package, const std::string& type_name,
                     bool with_request_header, TypeSet& out) {
  std::vector<Field> fields;
  if (with_request_header) {
    fields.push_back({"uint64", "client_guid_"});
    fields.push_back({"int64", "sequence_number_"});
  }
  std::map<std::string, Constant> constants;
  static const std::regex constant_re(R"(^(\w+)\s+([A-Z][A-Z0-9_]*)\s*=\s*(\S+)$)");
  static const std::regex field_re(R"(^([\w/]+(\[\d*\])?)\s+([a-z][a-z0-9_]*)$)");
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const auto c = line.find('#');
    if (c != std::string::npos) line.erase(c);
    line = trim(line);
    if (line.empty()) continue;
    std::smatch m;
    if (std::regex_match(line, m, constant_re)) {
      constants[m[2].str()] = {msgTypeToIdl(m[1].str(), package), m[3].str()};
    } else if (std::regex_match(line, m, field_re)) {
      fields.push_back({msgTypeToIdl(m[1].str(), package), m[3].str()});
    } else {
      throw std::runtime_error(type_name + ": unreadable line '" + line + "'");
    }
  }
  out.structs[type_name] = fields;
  if (!constants.empty()) {
    // rosidl puts a type's constants in module <Type>_Constants beside the struct.
    out.constant_modules[type_name.substr(0, type_name.size() - 1) + "_Constants"] = constants;
  }
}

}  // namespace

std::string msgTypeToIdl(const std::string& msg_type, const std::string& package) {
  static const std::regex re(R"(^([\w/]+)(\[(\d*)\])?$)");
  std::smatch m;
  if (!std::regex_match(msg_type, m, re)) throw std::runtime_error("bad .msg type: " + msg_type);
  const std::string base = m[1].str();
  std::string idl;
  if (const auto p = primitiveMap().find(base); p != primitiveMap().end()) {
    idl = p->second;
  } else if (const auto slash = base.find('/'); slash != std::string::npos) {
    idl = base.substr(0, slash) + "::msg::dds_::" + base.substr(slash + 1) + "_";
  } else if (!base.empty() && std::isupper(static_cast<unsigned char>(base[0]))) {
    idl = package + "::msg::dds_::" + base + "_";
  } else {
    throw std::runtime_error("unknown .msg primitive: " + base);
  }
  if (!m[2].matched) return idl;
  if (m[3].str().empty()) return "sequence<" + idl + ">";
  return idl + "[" + m[3].str() + "]";
}

void parseIdl(const std::string& text, const std::string& outer_module, TypeSet& out) {
  const std::string body = stripIdlComments(text);
  static const std::regex block_re(R"((struct|module)\s+(\w+)\s*\{([^{}]*)\})");
  static const std::regex const_re(R"(^const\s+(\w+)\s+(\w+)\s*=\s*(\S+)$)");
  for (std::sregex_iterator it(body.begin(), body.end(), block_re), end; it != end; ++it) {
    const std::string kind = (*it)[1].str();
    const std::string name = outer_module + "::" + (*it)[2].str();
    std::istringstream members((*it)[3].str());
    std::string decl;
    if (kind == "struct") {
      std::vector<Field> fields;
      while (std::getline(members, decl, ';')) {
        if (!trim(decl).empty()) fields.push_back(idlMember(decl));
      }
      out.structs[name] = fields;
    } else {
      std::map<std::string, Constant> constants;
      while (std::getline(members, decl, ';')) {
        const std::string d = trim(decl);
        if (d.empty()) continue;
        std::smatch m;
        if (!std::regex_match(d, m, const_re)) throw std::runtime_error("unreadable IDL constant: " + d);
        constants[m[2].str()] = {m[1].str(), m[3].str()};
      }
      out.constant_modules[name] = constants;
    }
  }
}

void parseMsg(const std::string& text, const std::string& package, const std::string& name, TypeSet& out) {
  parseMsgSection(text, package, package + "::msg::dds_::" + name + "_", false, out);
}

void parseSrv(const std::string& text, const std::string& package, const std::string& name, TypeSet& out) {
  static const std::regex separator(R"((^|\n)---[ \t]*(\r?\n|$))");
  std::smatch m;
  if (!std::regex_search(text, m, separator)) throw std::runtime_error(name + ".srv: no '---'");
  const std::string request = text.substr(0, m.position(0));
  const std::string response = text.substr(m.position(0) + m.length(0));
  const std::string prefix = package + "::srv::dds_::" + name;
  parseMsgSection(request, package, prefix + "_Request_", true, out);
  parseMsgSection(response, package, prefix + "_Response_", true, out);
}

}  // namespace semfuse::interop
