// Parsers that reduce semfuse's IDL (idl/semfuse/*.idl) and the ROS 2 interface package
// (idl/ros2/semfuse_msgs/{msg,srv}) to the same form: DDS type name -> ordered field list and
// constants, spelled as rosidl_generator_dds_idl would write them for rmw_cyclonedds. The sync
// test compares the two, so neither side can drift without a failing test.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace semfuse::interop {

struct Field {
  std::string type;  // IDL spelling: "double", "sequence<uint8>", "double[12]", "semfuse::msg::dds_::Frame_"
  std::string name;
  bool operator==(const Field& o) const { return type == o.type && name == o.name; }
};

// gtest prints fields as "type name" instead of raw bytes.
inline void PrintTo(const Field& f, std::ostream* os) { *os << f.type << " " << f.name; }

struct Constant {
  std::string type;
  std::string value;
  bool operator==(const Constant& o) const { return type == o.type && value == o.value; }
};

struct TypeSet {
  std::map<std::string, std::vector<Field>> structs;                        // full DDS name
  std::map<std::string, std::map<std::string, Constant>> constant_modules;  // full module name
};

// Parses the structs and constant modules of an IDL text whose types live in
// `outer_module` (e.g. "semfuse::msg::dds_"). Throws std::runtime_error on text it cannot read.
void parseIdl(const std::string& text, const std::string& outer_module, TypeSet& out);

// Parses one .msg text as type semfuse::msg::dds_::<name>_.
void parseMsg(const std::string& text, const std::string& package, const std::string& name, TypeSet& out);

// Parses one .srv text as <Name>_Request_ / <Name>_Response_, each starting with the
// rmw_cyclonedds request header (client_guid_, sequence_number_).
void parseSrv(const std::string& text, const std::string& package, const std::string& name, TypeSet& out);

// The IDL spelling of a .msg field type ("float64[12]" -> "double[12]", "Counter[]" ->
// "sequence<semfuse::msg::dds_::Counter_>"). Throws on an unknown primitive.
std::string msgTypeToIdl(const std::string& msg_type, const std::string& package);

}  // namespace semfuse::interop
