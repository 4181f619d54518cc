#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <CLI/CLI.hpp>

#include "semfuse/core/cli_config.hpp"

namespace semfuse {
namespace {

namespace fs = std::filesystem;

// A program with top-level, dotted (nested) and subcommand options, configured from a YAML file.
class YamlConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = fs::temp_directory_path() /
            ("semfuse_cli_config_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
             ".yaml");
    app_.add_option("--voxel-size", voxel_size_);
    app_.add_option("--volume.truncation", truncation_);
    app_.add_option("--camera-id", camera_id_);
    app_.add_option("--ids", ids_);
    app_.add_flag("--verbose", verbose_);
    query_ = app_.add_subcommand("query");
    query_->add_option("--timeout", timeout_);
    addYamlConfig(app_);
  }
  void TearDown() override { fs::remove(file_); }

  // Parses argv (program name first) after writing `yaml` as the config file.
  void parse(const std::string& yaml, std::vector<std::string> args) {
    std::ofstream(file_) << yaml;
    args.insert(args.begin(), {"--config", file_.string()});
    std::reverse(args.begin(), args.end());  // CLI11 takes the reversed argument vector
    app_.parse(args);
  }

  std::string parseError(const std::string& yaml) {
    try {
      parse(yaml, {});
    } catch (const CLI::ParseError& e) {
      return e.what();
    }
    return "<no error>";
  }

  fs::path file_;
  CLI::App app_{"test"};
  CLI::App* query_ = nullptr;
  double voxel_size_ = 0.05;
  double truncation_ = 0.1;
  std::string camera_id_ = "cam0";
  std::vector<int> ids_;
  bool verbose_ = false;
  double timeout_ = 1.0;
};

TEST_F(YamlConfigTest, FileSetsNestedListAndSubcommandValues) {
  parse("voxel-size: 0.02\nvolume:\n  truncation: 0.08\nids: [3, 1, 2]\nverbose: true\nquery:\n  timeout: 7.5\n", {});
  EXPECT_DOUBLE_EQ(voxel_size_, 0.02);
  EXPECT_DOUBLE_EQ(truncation_, 0.08);
  EXPECT_EQ(ids_, (std::vector<int>{3, 1, 2}));
  EXPECT_TRUE(verbose_);
  EXPECT_DOUBLE_EQ(timeout_, 7.5);
  EXPECT_EQ(camera_id_, "cam0");  // not in the file: default kept
}

TEST_F(YamlConfigTest, CommandLineOverridesTheFile) {
  parse("voxel-size: 0.02\ncamera-id: kitchen\n", {"--voxel-size", "0.03"});
  EXPECT_DOUBLE_EQ(voxel_size_, 0.03);
  EXPECT_EQ(camera_id_, "kitchen");
}

TEST_F(YamlConfigTest, UnknownKeyIsNamedWithLineAndKnownKeys) {
  const std::string error = parseError("voxel-size: 0.02\nvolume:\n  truncaton: 0.08\n");
  EXPECT_NE(error.find("unknown key 'volume.truncaton' (line 3)"), std::string::npos) << error;
  EXPECT_NE(error.find("known keys: voxel-size, volume.truncation, camera-id, ids, verbose, query: {...}"),
            std::string::npos)
      << error;
}

TEST_F(YamlConfigTest, UnknownKeyInASubcommandSection) {
  const std::string error = parseError("query:\n  timeot: 2\n");
  EXPECT_NE(error.find("unknown key 'query.timeot'"), std::string::npos) << error;
  EXPECT_NE(error.find("known keys of 'query': timeout"), std::string::npos) << error;
}

TEST_F(YamlConfigTest, MalformedYamlGivesLineAndColumn) {
  const std::string error = parseError("voxel-size: 0.02\nvolume: [1, 2\n");
  EXPECT_NE(error.find("malformed YAML at line"), std::string::npos) << error;
}

TEST_F(YamlConfigTest, WrongValueTypeIsAConversionError) {
  const std::string error = parseError("voxel-size: small\n");
  EXPECT_NE(error.find("voxel-size"), std::string::npos) << error;
  EXPECT_NE(error.find("small"), std::string::npos) << error;
}

TEST_F(YamlConfigTest, TopLevelMustBeAMap) {
  EXPECT_NE(parseError("- 1\n- 2\n").find("top level of a config file must be a map"), std::string::npos);
}

TEST_F(YamlConfigTest, WritesCurrentValuesAsNestedYaml) {
  parse("volume:\n  truncation: 0.08\n", {"--camera-id", "kitchen"});
  const std::string yaml = app_.config_to_str(false, false);
  EXPECT_NE(yaml.find("camera-id: kitchen"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("volume:\n  truncation: 0.08"), std::string::npos) << yaml;
}

}  // namespace
}  // namespace semfuse
