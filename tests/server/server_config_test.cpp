// The server's configuration declares each setting once: the volume's parameters, the fusion and
// query limits keep their defaults in their own structs, the volume flags come from its field
// table under their old names, and a parameter goes YAML -> server params -> map file -> params
// unchanged.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <CLI/CLI.hpp>

#include "semfuse/core/cli_config.hpp"
#include "semfuse/volume/map_file.hpp"
#include "semfuse/volume/volume_param_table.hpp"
#include "server_config.hpp"

using namespace semfuse;
using namespace semfuse::server;
namespace fs = std::filesystem;

namespace {

// The server's own options, parsed from `command_line` as semfuse-server parses its argv.
std::unique_ptr<CLI::App> parsedApp(ServerConfig& config, const std::string& command_line) {
  auto app = std::make_unique<CLI::App>("semfuse-server under test");
  app->option_defaults()->always_capture_default();
  addYamlConfig(*app);
  addServerOptions(*app, config);
  app->parse(command_line, false);
  return app;
}

class ServerConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("semfuse_server_config_" + std::to_string(::getpid()));
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(folder_ / name) << text;
    return folder_ / name;
  }
  fs::path folder_;
};

TEST_F(ServerConfigTest, DefaultsAreTheLibrariesOwnAndTheReadmesBayesRule) {
  ServerConfig config;
  auto app = parsedApp(config, "");
  EXPECT_EQ(volume::volumeParamsText(config.volume), volume::volumeParamsText(volume::VolumeParams{}));
  EXPECT_EQ(config.volume.label_rule, volume::LabelRule::kBayes);  // README: the server's default rule
  EXPECT_EQ(config.fusion.history_frames, FusionLimits{}.history_frames);
  EXPECT_EQ(config.fusion.pending_timeout_s, FusionLimits{}.pending_timeout_s);
  EXPECT_EQ(config.queries.max_raycast_pixels, QueryLimits{}.max_raycast_pixels);
  // --help shows the same defaults.
  EXPECT_EQ(app->get_option("--label-rule")->get_default_str(), "bayes");
  EXPECT_EQ(app->get_option("--voxel-size")->get_default_str(), "0.01");
  EXPECT_EQ(app->get_option("--max-label-score")->get_default_str(), "16");
  EXPECT_EQ(app->get_option("--color")->get_default_str(), "1");  // CLI11 writes a bool as 1 or 0
  EXPECT_EQ(app->get_option("--history-frames")->get_default_str(), "120");
  // The volume the server builds differs from the defaults only by what the legend says.
  auto legend = serverLegend(config);
  ASSERT_TRUE(legend.ok()) << legend.error();
  auto params = serverVolumeParams(config, legend.value());
  ASSERT_TRUE(params.ok()) << params.error();
  volume::VolumeParams expected;
  expected.label_classes = static_cast<int>(legend.value().labels.size());
  expected.background_labels = legend.value().background_ids;
  EXPECT_EQ(volume::volumeParamsText(params.value()), volume::volumeParamsText(expected));
}

TEST_F(ServerConfigTest, EveryFlagAndConfigKeyKeepsItsName) {
  ServerConfig config;
  auto app = parsedApp(config, "");
  for (const char* flag : {"--voxel-size",
                           "--truncation",
                           "--max-weight",
                           "--weight-dropoff",
                           "--max-label-score",
                           "--label-rule",
                           "--min-depth",
                           "--max-depth",
                           "--color",
                           "--legend",
                           "--background-labels",
                           "--history-frames",
                           "--history-megabytes",
                           "--pending-segmentations",
                           "--pending-timeout",
                           "--queue-per-camera",
                           "--max-queue-wait",
                           "--max-raycast-pixels",
                           "--mesh-chunk-bytes",
                           "--map",
                           "--autosave-period",
                           "--refine-poses",
                           "--track-color-weight",
                           "--status-period",
                           "--stale-after"})
    EXPECT_NE(app->get_option_no_throw(flag), nullptr) << flag;
  // The config files the project ships read as before.
  for (const char* file : {"deploy/demo/synthetic.yaml", "deploy/demo/7scenes.yaml"}) {
    ServerConfig shipped;
    EXPECT_NO_THROW(parsedApp(shipped, "--config " + (fs::path(SEMFUSE_SOURCE_DIR) / file).string())) << file;
    EXPECT_EQ(shipped.volume.label_rule, volume::LabelRule::kBayes) << file;
  }
}

TEST_F(ServerConfigTest, AParameterGoesFromYamlThroughTheMapFileUnchanged) {
  const fs::path yaml = write("server.yaml",
                              "legend: synthetic\n"
                              "voxel-size: 0.03\n"
                              "truncation: 0.15\n"
                              "max-weight: 100\n"
                              "weight-dropoff: 0.5\n"
                              "max-label-score: 12.5\n"
                              "label-rule: majority\n"
                              "min-depth: 0.3\n"
                              "max-depth: 3.5\n"
                              "background-labels: [2, 7]\n"
                              "color: false\n"
                              "history-frames: 30\n"
                              "pending-timeout: 2.5\n");
  ServerConfig config;
  parsedApp(config, "--config " + yaml.string() + " --max-depth 4.5");  // a flag wins over the file
  EXPECT_EQ(config.fusion.history_frames, 30u);
  EXPECT_EQ(config.fusion.pending_timeout_s, 2.5);
  auto legend = serverLegend(config);
  ASSERT_TRUE(legend.ok()) << legend.error();
  auto params = serverVolumeParams(config, legend.value());
  ASSERT_TRUE(params.ok()) << params.error();
  const volume::VolumeParams& p = params.value();
  EXPECT_EQ(p.voxel_size, 0.03);
  EXPECT_EQ(p.truncation, 0.15);
  EXPECT_EQ(p.max_weight, 100.0f);
  EXPECT_EQ(p.weight_dropoff, 0.5f);
  EXPECT_EQ(p.max_label_score, 12.5f);
  EXPECT_EQ(p.label_rule, volume::LabelRule::kMajority);
  EXPECT_EQ(p.min_depth, 0.3f);
  EXPECT_EQ(p.max_depth, 4.5f);
  EXPECT_FALSE(p.integrate_color);
  EXPECT_EQ(p.label_classes, static_cast<int>(legend.value().labels.size()));
  for (LabelId id : {LabelId{2}, LabelId{7}})
    EXPECT_NE(std::find(p.background_labels.begin(), p.background_labels.end(), id), p.background_labels.end()) << id;

  const fs::path map = folder_ / "map.vdb";
  ASSERT_TRUE(volume::saveMap(volume::LabeledVolume(p), legend.value(), map).ok());
  auto loaded = volume::loadMap(map);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(volume::volumeParamsText(loaded.value().volume.params()), volume::volumeParamsText(p));
}

TEST_F(ServerConfigTest, AValueOutsideItsRangeIsRefusedWithTheTablesMessage) {
  ServerConfig config;
  try {
    parsedApp(config, "--max-weight 5000");
    FAIL() << "--max-weight 5000 was accepted";
  } catch (const CLI::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("max_weight must be a finite number in [1, 2048], got 5000"),
              std::string::npos)
        << e.what();
  }
  try {
    parsedApp(config, "--label-rule vote");
    FAIL() << "--label-rule vote was accepted";
  } catch (const CLI::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown label rule 'vote' (evidence, majority or bayes)"), std::string::npos)
        << e.what();
  }
  // A legend beyond the top-5 rules' 10-bit ids names the flag to change.
  ServerConfig wide;
  LabelLegend legend{"wide", {{1, "floor", {1, 1, 1}}, {2000, "rare", {2, 2, 2}}}, {}};
  auto params = serverVolumeParams(wide, legend);
  ASSERT_FALSE(params.ok());
  EXPECT_EQ(params.errorCode(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(params.error(),
            "--label-rule bayes keeps label ids up to 1023, but legend 'wide' has id 2000; use --label-rule evidence");
}

TEST_F(ServerConfigTest, TrackingColourWeightComesFromTheFileAndIsRangeChecked) {
  // A sensor whose colour is not registered to its depth tracks on depth alone.
  ServerConfig config;
  const fs::path yaml = write("tracking.yaml", "track-color-weight: 0\n");
  parsedApp(config, "--config " + yaml.string());
  EXPECT_EQ(config.track_color_weight, 0.0f);
  ServerConfig defaults;
  parsedApp(defaults, "");
  EXPECT_EQ(defaults.track_color_weight, tracking::TrackerParams{}.color_weight);
  ServerConfig negative;
  EXPECT_THROW(parsedApp(negative, "--track-color-weight -1"), CLI::ParseError);
}

TEST_F(ServerConfigTest, AnEmptyNumberIsRefusedNotReadAsZero) {
  // CLI11 turns "" into 0; a tag with no value is an empty scalar in YAML.
  for (const std::string text : {"voxel-size: \"\"\n", "voxel-size: !0.+5 # 5 cm\n", "queue-per-camera: ''\n"}) {
    ServerConfig config;
    const fs::path yaml = write("empty.yaml", text);
    try {
      parsedApp(config, "--config " + yaml.string());
      FAIL() << text << " was accepted: voxel size " << config.volume.voxel_size;
    } catch (const CLI::ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("has an empty value"), std::string::npos) << e.what();
    }
  }
  ServerConfig flag;
  EXPECT_THROW(parsedApp(flag, "--voxel-size \"\""), CLI::ParseError);
}

TEST_F(ServerConfigTest, TheMaximumQueueWaitIsSecondsWithinAMinute) {
  ServerConfig defaults;
  auto app = parsedApp(defaults, "");
  EXPECT_EQ(defaults.max_queue_wait_s, 0.1);
  EXPECT_EQ(app->get_option("--max-queue-wait")->get_default_str(), "0.1");
  ServerConfig off;
  parsedApp(off, "--max-queue-wait 0");
  EXPECT_EQ(off.max_queue_wait_s, 0.0);
  ServerConfig from_yaml;
  parsedApp(from_yaml, "--config " + write("wait.yaml", "max-queue-wait: 0.25\n").string());
  EXPECT_EQ(from_yaml.max_queue_wait_s, 0.25);
  for (const char* bad : {"-0.1", "nan", "inf", "61", "0.1s"}) {
    ServerConfig config;
    EXPECT_THROW(parsedApp(config, std::string("--max-queue-wait ") + bad), CLI::ParseError) << bad;
  }
}

}  // namespace

// What semfuse-server --print-config writes (the app's configuration as YAML, defaults included)
// reads back through --config to the same configuration, section keys and lists included.
TEST_F(ServerConfigTest, ThePrintedConfigurationReadsBackToTheSame) {
  ServerConfig given;
  auto app = parsedApp(given,
                       "--voxel-size 0.02 --label-rule evidence --background-labels 3 4 --objects-rate 2.5 "
                       "--map-updates.rate 4 --esdf --esdf.max-distance 1.5");
  const std::string printed = app->config_to_str(/*default_also=*/true, /*write_description=*/false);
  EXPECT_NE(printed.find("voxel-size: 0.02"), std::string::npos) << printed;
  EXPECT_NE(printed.find("map-updates:"), std::string::npos) << printed;

  ServerConfig read;
  auto reread = parsedApp(read, "--config " + write("printed.yaml", printed).string());
  EXPECT_EQ(reread->config_to_str(true, false), printed);
  EXPECT_EQ(volume::volumeParamsText(read.volume), volume::volumeParamsText(given.volume));
  EXPECT_EQ(read.volume.voxel_size, 0.02);
  EXPECT_EQ(read.volume.label_rule, volume::LabelRule::kEvidence);
  EXPECT_EQ(read.volume.background_labels, (std::vector<LabelId>{3, 4}));
  EXPECT_EQ(read.objects_rate_hz, 2.5);
  EXPECT_EQ(read.map_updates.rate_hz, 4.0);
  EXPECT_TRUE(read.esdf.enabled);  // a flag and a section at once: esdf.enabled in the file
  EXPECT_EQ(read.esdf.field.max_distance, 1.5);
  EXPECT_EQ(read.fusion.history_frames, given.fusion.history_frames);
}
