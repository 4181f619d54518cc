// The field table of VolumeParams: every field has one row with its own key and flag; the
// per-field checks of validate() come from the rows' ranges with one wording; a map file stores
// every field under "semfuse:<key>" and gives back exactly what was saved; maps written by
// earlier builds still load.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include "semfuse/volume/map_file.hpp"
#include "semfuse/volume/volume_param_table.hpp"

namespace semfuse::volume {
namespace {
namespace fs = std::filesystem;

// Every field as text, by key: two VolumeParams are the same when these are.
std::map<std::string, std::string> fieldsOf(const VolumeParams& params) {
  std::map<std::string, std::string> fields;
  forEachVolumeParam(params, [&fields](const ParamField& field, const auto& value) {
    using T = std::decay_t<decltype(value)>;
    std::ostringstream text;
    if constexpr (std::is_same_v<T, LabelRule>) {
      text << labelRuleName(value);
    } else if constexpr (std::is_same_v<T, std::vector<LabelId>>) {
      for (LabelId id : value) text << id << ' ';
    } else {
      text << value;
    }
    fields[field.key] = text.str();
  });
  return fields;
}

// Parameters with every field away from its default.
VolumeParams unusualParams() {
  VolumeParams p;
  p.voxel_size = 0.03;
  p.truncation = 0.15;
  p.max_weight = 100.0f;
  p.weight_dropoff = 0.5f;
  p.max_label_score = 12.5f;
  p.label_rule = LabelRule::kMajority;
  p.label_likelihood = 0.75f;
  p.label_classes = 41;
  p.min_depth = 0.3f;
  p.max_depth = 3.5f;
  p.background_labels = {2, 7};
  p.integrate_color = false;
  return p;
}

}  // namespace

TEST(VolumeParamTable, EveryFieldHasOneRowWithItsOwnKeyAndFlag) {
  std::set<std::string> keys, flags;
  int rows = 0;
  const VolumeParams defaults_struct;
  forEachVolumeParam(defaults_struct, [&](const ParamField& field, const auto&) {
    ++rows;
    EXPECT_TRUE(keys.insert(field.key).second) << field.key;
    if (field.flag) {
      EXPECT_TRUE(flags.insert(field.flag).second) << field.flag;
    }
    EXPECT_NE(std::string(field.doc), "") << field.key;
  });
  EXPECT_EQ(rows, 12);
  // A new member without a row would be missing from map files and flags: unusualParams() sets
  // every member, and each differs from the default in exactly one row.
  const auto defaults = fieldsOf(VolumeParams{}), unusual = fieldsOf(unusualParams());
  ASSERT_EQ(defaults.size(), 12u);
  for (const auto& [key, value] : defaults) EXPECT_NE(unusual.at(key), value) << key;
}

TEST(VolumeParamTable, RangesGiveOneWordingForEveryField) {
  VolumeParams p;
  EXPECT_TRUE(p.validate().ok());
  p.voxel_size = 0;
  EXPECT_EQ(p.validate().error(), "voxel_size must be a finite number > 0, got 0");
  EXPECT_EQ(p.validate().errorCode(), ErrorCode::kInvalidArgument);
  p = {};
  p.max_weight = 5000;
  EXPECT_EQ(p.validate().error(), "max_weight must be a finite number in [1, 2048], got 5000");
  p = {};
  p.weight_dropoff = 0.0f;  // a drop from the surface itself would weigh noise in front above it
  EXPECT_EQ(p.validate().error(), "weight_dropoff must be a finite number in (0, 1], got 0");
  p.weight_dropoff = 1.0f;
  EXPECT_TRUE(p.validate().ok());
  p = {};
  p.max_label_score = std::nanf("");
  EXPECT_EQ(p.validate().error(), "max_label_score must be a finite number in (0, 2048], got nan");
  p = {};
  p.label_likelihood = 1.0f;
  EXPECT_EQ(p.validate().error(), "label_likelihood must be a finite number in (0, 1), got 1");
  p = {};
  p.label_classes = 1;
  EXPECT_EQ(p.validate().error(), "label_classes must be a finite number in [2, 65535], got 1");
  p = {};
  p.min_depth = -0.5f;
  EXPECT_EQ(p.validate().error(), "min_depth must be a finite number > 0, got -0.5");
  // What one field's range cannot say is checked across fields.
  p = {};
  p.truncation = 0.005;
  EXPECT_EQ(p.validate().error(), "truncation must be at least one voxel (0.01 m), got 0.005");
  p = {};
  p.min_depth = 3;
  p.max_depth = 2;
  EXPECT_EQ(p.validate().error(), "depth range must satisfy min_depth < max_depth, got [3, 2]");
  p = {};
  p.label_classes = 4;
  p.label_likelihood = 0.2f;
  EXPECT_EQ(p.validate().error(), "label_likelihood must be above chance (1/label_classes = 0.25), got 0.2");
}

TEST(VolumeParamTable, RangeTextAndBounds) {
  const ParamRange half_open{0.0, 2048.0, true, false};
  EXPECT_EQ(half_open.text(), "in (0, 2048]");
  EXPECT_FALSE(half_open.contains(0.0));
  EXPECT_TRUE(half_open.contains(2048.0));
  EXPECT_FALSE(half_open.contains(2048.5));
  const ParamRange at_least_one{1.0, std::numeric_limits<double>::infinity()};
  EXPECT_EQ(at_least_one.text(), ">= 1");
  EXPECT_TRUE(at_least_one.contains(1.0));
  EXPECT_FALSE(at_least_one.contains(std::numeric_limits<double>::infinity()));
}

class VolumeParamsInMapFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("semfuse_param_table_" + std::to_string(::getpid()));
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
};

TEST_F(VolumeParamsInMapFiles, EveryFieldIsStoredUnderItsKeyAndReadBack) {
  const VolumeParams saved = unusualParams();
  const LabeledVolume volume(saved);
  const fs::path path = folder_ / "unusual.vdb";
  ASSERT_TRUE(saveMap(volume, LabelLegend{"test", {{1, "thing", {1, 2, 3}}}, {}}, path).ok());

  auto loaded = loadMap(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(fieldsOf(loaded.value().volume.params()), fieldsOf(saved));

  // Under "semfuse:<key>", with the metadata types map files have always had.
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::map<std::string, std::string> types{
      {"voxel_size", "double"},      {"truncation", "double"},        {"max_weight", "float"},
      {"weight_dropoff", "float"},   {"max_label_score", "float"},    {"label_rule", "string"},
      {"label_likelihood", "float"}, {"label_classes", "int32"},      {"min_depth", "float"},
      {"max_depth", "float"},        {"background_labels", "string"}, {"integrate_color", "bool"}};
  forEachVolumeParam(saved, [&](const ParamField& field, const auto&) {
    // OpenVDB file metadata: the name, then the length-prefixed type name.
    const std::string key = std::string("semfuse:") + field.key;
    const std::size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos) << key;
    const std::string type = types.at(field.key);
    EXPECT_EQ(bytes.substr(at + key.size() + 4, type.size()), type) << key;
  });
}

TEST_F(VolumeParamsInMapFiles, AMapWrittenByAnEarlierBuildStillLoads) {
  // The fuzz corpus's seed map (fuzz/support/tiny_map.hpp), written by the hand-listed metadata
  // code this table replaced.
  auto loaded = loadMap(fs::path(SEMFUSE_SOURCE_DIR) / "fuzz/corpus/map_file/seed-tiny.vdb");
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const VolumeParams& params = loaded.value().volume.params();
  EXPECT_EQ(params.voxel_size, 0.05);
  EXPECT_EQ(params.truncation, 0.2);
  EXPECT_TRUE(params.integrate_color);
  EXPECT_EQ(params.weight_dropoff, VolumeParams{}.weight_dropoff);  // stored since version 4
  EXPECT_GT(loaded.value().volume.observedVoxels(), 0u);
}

}  // namespace semfuse::volume
