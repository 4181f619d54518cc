// Map files: save -> load reproduces the packed voxels bit for bit with all metadata; the tsdf is
// a level set other tools can read; damaged files fail with a message and no partial map.
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <openvdb/io/File.h>

#include "analytic_scene.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/map_file.hpp"

namespace semfuse::volume {
namespace {
namespace fs = std::filesystem;

class MapFile : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("semfuse_map_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  // A plane seen from two poses with labels and colour.
  static LabeledVolume labeledPlane() {
    VolumeParams params;
    params.background_labels = {3};
    params.max_label_score = 8;
    LabeledVolume volume(params);
    const PinholeIntrinsics k = testing::smallCamera();
    for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.2, 0.1, 0.05)}) {
      const Pose pose = testing::lookAt(eye, {0, 0, 1});
      const cv::Mat depth = testing::renderPlane(k, pose, {0, 0, -1}, -1.0);
      cv::Mat labels(k.height, k.width, CV_16UC1, cv::Scalar(4));
      labels.colRange(80, 160).setTo(9);
      const cv::Mat confidence(k.height, k.width, CV_32FC1, cv::Scalar(0.6));
      const cv::Mat color(k.height, k.width, CV_8UC3, cv::Scalar(10, 120, 230));
      EXPECT_TRUE(integrate(volume, depth, color, labels, confidence, k, pose).ok());
    }
    return volume;
  }

  static LabelLegend legend() { return {"test", {{0, "unlabeled", {0, 0, 0}}, {4, "chair", {200, 10, 10}}, {9, "dining table", {1, 2, 3}}}, {3}}; }

  fs::path folder_;
};

template <typename TreeT>
void expectSameLeaves(const TreeT& a, const TreeT& b) {
  ASSERT_EQ(a.leafCount(), b.leafCount());
  ASSERT_TRUE(a.hasSameTopology(b));
  for (auto leaf = a.cbeginLeaf(); leaf; ++leaf) {
    const auto* other = b.probeConstLeaf(leaf->origin());
    ASSERT_NE(other, nullptr);
    EXPECT_EQ(std::memcmp(leaf->buffer().data(), other->buffer().data(), sizeof(typename TreeT::ValueType) * leaf->SIZE), 0)
        << "leaf " << leaf->origin();
  }
}

TEST_F(MapFile, RoundTripIsBitIdentical) {
  const LabeledVolume volume = labeledPlane();
  ASSERT_GT(volume.observedVoxels(), 10000u);
  const fs::path path = folder_ / "map.vdb";
  ASSERT_TRUE(saveMap(volume, legend(), path, {{"camera", "kinect v1"}, {"note", "plane"}}).ok());
  // Atomic write leaves only the map in the folder.
  EXPECT_EQ(std::distance(fs::directory_iterator(folder_), fs::directory_iterator()), 1);

  auto loaded = loadMap(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const LoadedMap& map = loaded.value();
  expectSameLeaves(volume.geometryGrid().tree(), map.volume.geometryGrid().tree());
  ASSERT_NE(map.volume.colorGrid(), nullptr);
  expectSameLeaves(volume.colorGrid()->tree(), map.volume.colorGrid()->tree());
  EXPECT_EQ(map.volume.observedVoxels(), volume.observedVoxels());
  EXPECT_EQ(map.volume.framesIntegrated(), 2u);
  EXPECT_EQ(map.volume.params().voxel_size, volume.params().voxel_size);
  EXPECT_EQ(map.volume.params().truncation, volume.params().truncation);
  EXPECT_EQ(map.volume.params().max_label_score, 8.0f);
  EXPECT_EQ(map.volume.params().background_labels, std::vector<LabelId>{3});
  EXPECT_EQ(map.format_version, kMapFormatVersion);
  EXPECT_EQ(map.legend.name, "test");
  ASSERT_EQ(map.legend.labels.size(), 3u);
  EXPECT_EQ(map.legend.labels[2].name, "dining table");
  EXPECT_EQ(map.legend.labels[2].rgb, (std::array<uint8_t, 3>{1, 2, 3}));
  EXPECT_EQ(map.legend.background_ids, std::vector<LabelId>{3});
  EXPECT_EQ(map.extra.at("camera"), "kinect v1");
  EXPECT_EQ(map.extra.at("note"), "plane");
  EXPECT_EQ(map.volume.voxel({0, 0, 100}).label, volume.voxel({0, 0, 100}).label);
}

TEST_F(MapFile, TsdfIsALevelSetOtherToolsCanRead) {
  const LabeledVolume volume = labeledPlane();
  const fs::path path = folder_ / "map.vdb";
  ASSERT_TRUE(saveMap(volume, legend(), path).ok());
  openvdb::io::File file(path.string());
  file.open();
  auto tsdf = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("tsdf"));
  file.close();
  ASSERT_NE(tsdf, nullptr);
  EXPECT_EQ(tsdf->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_NEAR(tsdf->voxelSize().x(), 0.01, 1e-12);
  EXPECT_NEAR(tsdf->background(), 0.04f, 1e-4f);  // stored as half, like the values
  EXPECT_EQ(tsdf->tree().getValue({0, 0, 98}), volume.voxel({0, 0, 98}).tsdf);
  EXPECT_NEAR(tsdf->tree().getValue({0, 0, 98}), 0.02f, 1e-3f);
}

TEST_F(MapFile, SavingReplacesAnExistingMap) {
  const fs::path path = folder_ / "map.vdb";
  ASSERT_TRUE(saveMap(LabeledVolume(), legend(), path).ok());
  ASSERT_TRUE(saveMap(labeledPlane(), legend(), path).ok());
  auto loaded = loadMap(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded.value().volume.framesIntegrated(), 2u);
}

TEST_F(MapFile, UnwritableFolderFailsCleanly) {
  const Status s = saveMap(LabeledVolume(), legend(), folder_ / "missing" / "map.vdb");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("cannot create"), std::string::npos) << s.error();
}

TEST_F(MapFile, TruncatedOrCorruptFilesFailWithAMessage) {
  const fs::path path = folder_ / "map.vdb";
  ASSERT_TRUE(saveMap(labeledPlane(), legend(), path).ok());
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000u);

  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(folder_ / name, std::ios::binary) << content;
    return folder_ / name;
  };
  for (std::size_t keep : {bytes.size() / 2, bytes.size() - 10, std::size_t{100}, std::size_t{0}}) {
    auto r = loadMap(write("truncated.vdb", bytes.substr(0, keep)));
    ASSERT_FALSE(r.ok()) << "kept " << keep << " bytes";
    EXPECT_NE(r.error().find("truncated.vdb"), std::string::npos) << r.error();
  }
  // Flipped bytes in the voxel data: caught by the format or by the checksum.
  for (std::size_t at : {bytes.size() / 3, bytes.size() / 2, bytes.size() * 3 / 4}) {
    std::string corrupt = bytes;
    for (std::size_t i = at; i < at + 16; ++i) corrupt[i] = static_cast<char>(~corrupt[i]);
    auto r = loadMap(write("corrupt.vdb", corrupt));
    EXPECT_FALSE(r.ok()) << "flipped at " << at;
  }
  auto not_vdb = loadMap(write("text.vdb", "this is not a map"));
  ASSERT_FALSE(not_vdb.ok());
  EXPECT_NE(not_vdb.error().find("not a readable OpenVDB file"), std::string::npos) << not_vdb.error();
  auto missing = loadMap(folder_ / "nothing.vdb");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("cannot open"), std::string::npos) << missing.error();
}

TEST_F(MapFile, PlainVdbWithoutSemfuseMetadataIsRefused) {
  const fs::path path = folder_ / "plain.vdb";
  openvdb::io::File file(path.string());
  file.write({openvdb::FloatGrid::create(1.0f)});
  file.close();
  auto r = loadMap(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("not a semfuse map"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace semfuse::volume
