// The ROS 2 interface package (idl/ros2/semfuse_msgs) must describe exactly the wire types of
// idl/semfuse/*.idl: same type names, same fields in the same order with the same types, same
// constants. Otherwise `ros2 topic echo /semfuse/status` on rmw_cyclonedds would decode garbage.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "ros_interface_parse.hpp"

namespace fs = std::filesystem;
using namespace semfuse::interop;

namespace {

const fs::path kSource = SEMFUSE_SOURCE_DIR;
const fs::path kPackage = kSource / "idl/ros2/semfuse_msgs";

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TypeSet idlTypes() {
  TypeSet t;
  parseIdl(readText(kSource / "idl/semfuse/msg.idl"), "semfuse::msg::dds_", t);
  parseIdl(readText(kSource / "idl/semfuse/srv.idl"), "semfuse::srv::dds_", t);
  return t;
}

TypeSet rosTypes() {
  TypeSet t;
  for (const auto& e : fs::directory_iterator(kPackage / "msg")) {
    if (e.path().extension() == ".msg") parseMsg(readText(e.path()), "semfuse", e.path().stem(), t);
  }
  for (const auto& e : fs::directory_iterator(kPackage / "srv")) {
    if (e.path().extension() == ".srv") parseSrv(readText(e.path()), "semfuse", e.path().stem(), t);
  }
  return t;
}

std::string describe(const std::vector<Field>& fields) {
  std::string s;
  for (const auto& f : fields) s += "  " + f.type + " " + f.name + "\n";
  return s;
}

}  // namespace

TEST(RosInterfaceSync, EveryIdlStructHasAnIdenticalRosInterface) {
  const TypeSet idl = idlTypes();
  const TypeSet ros = rosTypes();
  ASSERT_GE(idl.structs.size(), 45u);  // 21 messages + 12 services x 2
  for (const auto& [name, fields] : idl.structs) {
    const auto it = ros.structs.find(name);
    ASSERT_NE(it, ros.structs.end()) << name << " has no .msg/.srv in " << kPackage;
    EXPECT_EQ(it->second, fields) << name << "\nIDL:\n" << describe(fields) << ".msg/.srv:\n" << describe(it->second);
  }
  for (const auto& [name, fields] : ros.structs) {
    EXPECT_TRUE(idl.structs.count(name)) << name << " is in the ROS package but not in idl/semfuse";
  }
}

TEST(RosInterfaceSync, ConstantsAgree) {
  const TypeSet idl = idlTypes();
  const TypeSet ros = rosTypes();
  for (const auto& [module, constants] : idl.constant_modules) {
    if (module == "semfuse::srv::dds_::Status_Constants") continue;  // checked below
    const auto it = ros.constant_modules.find(module);
    ASSERT_NE(it, ros.constant_modules.end()) << module << " missing from the ROS package";
    EXPECT_EQ(it->second, constants) << module;
  }
  // .srv files cannot hold a free constant module: each response repeats the reply status codes.
  const auto& status = idl.constant_modules.at("semfuse::srv::dds_::Status_Constants");
  int responses = 0;
  for (const auto& [name, fields] : ros.structs) {
    if (name.find("_Response_") == std::string::npos) continue;
    ++responses;
    const std::string module = name.substr(0, name.size() - 1) + "_Constants";
    ASSERT_TRUE(ros.constant_modules.count(module)) << name << " lacks the status constants";
    EXPECT_EQ(ros.constant_modules.at(module), status) << module;
  }
  EXPECT_EQ(responses, 12);
  for (const auto& [module, constants] : ros.constant_modules) {
    if (module.find("_Response_Constants") != std::string::npos) continue;
    EXPECT_TRUE(idl.constant_modules.count(module)) << module << " exists only in the ROS package";
  }
}

TEST(RosInterfaceSync, ColconCMakeListsNamesEveryInterfaceFile) {
  const std::string cmake = readText(kPackage / "CMakeLists.txt");
  int files = 0;
  for (const char* dir : {"msg", "srv"}) {
    for (const auto& e : fs::directory_iterator(kPackage / dir)) {
      ++files;
      const std::string rel = std::string(dir) + "/" + e.path().filename().string();
      EXPECT_NE(cmake.find(rel), std::string::npos) << rel << " not in rosidl_generate_interfaces";
    }
  }
  EXPECT_EQ(files, 35);
  // The package must be called semfuse: rmw_cyclonedds derives the DDS type names from it.
  EXPECT_NE(readText(kPackage / "package.xml").find("<name>semfuse</name>"), std::string::npos);
  EXPECT_TRUE(std::regex_search(cmake, std::regex(R"(project\(semfuse\))")));
}

// The comparison must be able to fail: a swapped field order, a changed type and a renamed
// field are each detected.
TEST(RosInterfaceSync, ParsersSeeOrderTypeAndNameDifferences) {
  TypeSet idl;
  parseIdl(
      "module semfuse { module msg { module dds_ {\n"
      "  struct Counter_ { string reason; string camera_id; uint64 count; };\n"
      "  struct Frame_ { double camera_to_world[12]; sequence<uint8> depth; };\n"
      "}; }; };",
      "semfuse::msg::dds_", idl);
  auto rosOf = [](const std::string& text) {
    TypeSet t;
    parseMsg(text, "semfuse", "Counter", t);
    return t.structs.at("semfuse::msg::dds_::Counter_");
  };
  const auto& counter = idl.structs.at("semfuse::msg::dds_::Counter_");
  EXPECT_EQ(rosOf("string reason\nstring camera_id  # c\nuint64 count\n"), counter);
  EXPECT_NE(rosOf("string camera_id\nstring reason\nuint64 count\n"), counter);
  EXPECT_NE(rosOf("string reason\nstring camera_id\nuint32 count\n"), counter);
  EXPECT_NE(rosOf("string reason\nstring camera\nuint64 count\n"), counter);

  const std::vector<Field> frame = {{"double[12]", "camera_to_world"}, {"sequence<uint8>", "depth"}};
  EXPECT_EQ(idl.structs.at("semfuse::msg::dds_::Frame_"), frame);
  EXPECT_EQ(msgTypeToIdl("float64[12]", "semfuse"), "double[12]");
  EXPECT_EQ(msgTypeToIdl("Counter[]", "semfuse"), "sequence<semfuse::msg::dds_::Counter_>");
  EXPECT_EQ(msgTypeToIdl("std_msgs/Header", "semfuse"), "std_msgs::msg::dds_::Header_");
  EXPECT_THROW(msgTypeToIdl("float128", "semfuse"), std::runtime_error);
  TypeSet bad;
  EXPECT_THROW(parseMsg("uint8 x y z\n", "semfuse", "Bad", bad), std::runtime_error);
  EXPECT_THROW(parseSrv("uint8 x\n", "semfuse", "NoSeparator", bad), std::runtime_error);
}
