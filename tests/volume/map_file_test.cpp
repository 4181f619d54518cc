// Map files: save -> load reproduces the packed voxels bit for bit with all metadata; the tsdf is
// a level set other tools can read; damaged files fail with a message and no partial map, refused
// by the integrity trailer before OpenVDB reads them; temporary files of dead writers are removed.
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <openvdb/io/File.h>

#include "analytic_scene.hpp"
#include "semfuse/volume/instance_integration.hpp"
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

  // A plane seen from two poses with labels and colour, fused with the evidence rule (which
  // version 2 files of it load with too).
  static LabeledVolume labeledPlane() {
    VolumeParams params;
    params.label_rule = LabelRule::kEvidence;
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

  static LabelLegend legend() {
    return {"test", {{0, "unlabeled", {0, 0, 0}}, {4, "chair", {200, 10, 10}}, {9, "dining table", {1, 2, 3}}}, {3}};
  }

  fs::path folder_;
};

template <typename TreeT>
void expectSameLeaves(const TreeT& a, const TreeT& b) {
  ASSERT_EQ(a.leafCount(), b.leafCount());
  ASSERT_TRUE(a.hasSameTopology(b));
  for (auto leaf = a.cbeginLeaf(); leaf; ++leaf) {
    const auto* other = b.probeConstLeaf(leaf->origin());
    ASSERT_NE(other, nullptr);
    EXPECT_EQ(
        std::memcmp(leaf->buffer().data(), other->buffer().data(), sizeof(typename TreeT::ValueType) * leaf->SIZE), 0)
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

TEST_F(MapFile, KeepsPanopticInstanceEvidenceAndTheNextInstanceId) {
  LabeledVolume volume = labeledPlane();
  const fs::path plain = folder_ / "plain.vdb";
  ASSERT_TRUE(saveMap(volume, legend(), plain).ok());
  auto without = loadMap(plain);
  ASSERT_TRUE(without.ok()) << without.error();
  EXPECT_EQ(without.value().volume.instanceGrid(), nullptr);  // class-only maps carry none

  // Two instances side by side on the plane, seen from the first pose.
  const PinholeIntrinsics k = testing::smallCamera();
  const Pose pose = testing::lookAt({0, 0, 0}, {0, 0, 1});
  const cv::Mat depth = testing::renderPlane(k, pose, {0, 0, -1}, -1.0);
  cv::Mat labels(k.height, k.width, CV_16UC1, cv::Scalar(4));
  cv::Mat instances(k.height, k.width, CV_16UC1, cv::Scalar(1));
  instances.colRange(k.width / 2, k.width).setTo(2);
  auto fused = integrateInstances(volume, depth, labels, instances, k, pose);
  ASSERT_TRUE(fused.ok()) << fused.error();
  ASSERT_EQ(fused.value().created, 2u);
  ASSERT_NE(volume.instanceGrid(), nullptr);
  EXPECT_TRUE(volume.instancesSeenApart(2, 1));  // one segmentation named them as two segments

  const fs::path path = folder_ / "panoptic.vdb";
  ASSERT_TRUE(saveMap(volume, legend(), path).ok());
  auto loaded = loadMap(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const LabeledVolume& map = loaded.value().volume;
  ASSERT_NE(map.instanceGrid(), nullptr);
  expectSameLeaves(volume.instanceGrid()->tree(), map.instanceGrid()->tree());
  EXPECT_EQ(map.nextInstanceId(), volume.nextInstanceId());
  EXPECT_EQ(map.nextInstanceId(), 3u);
  EXPECT_EQ(map.instancePairsSeenApart(), volume.instancePairsSeenApart());
  EXPECT_TRUE(map.instancesSeenApart(1, 2));
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

// CRC-64/XZ written bit by bit from its definition, independent of the table-driven one in the
// library: the oracle for the trailer and the tool to re-seal files whose content a test edits.
uint64_t crc64xz(const std::string& bytes) {
  uint64_t crc = ~uint64_t{0};
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ ((crc & 1u) ? 0xC96C5795D7870F42ull : 0);
  }
  return ~crc;
}

uint64_t littleEndianAt(const std::string& bytes, std::size_t at) {
  uint64_t value = 0;
  for (int i = 7; i >= 0; --i) value = value << 8 | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

void putLittleEndianAt(std::string& bytes, std::size_t at, uint64_t value, int size = 8) {
  for (int i = 0; i < size; ++i) bytes[at + i] = static_cast<char>((value >> (8 * i)) & 0xFFu);
}

class DamagedMapFile : public MapFile {
 protected:
  void SetUp() override {
    MapFile::SetUp();
    const fs::path path = folder_ / "map.vdb";
    ASSERT_TRUE(saveMap(labeledPlane(), legend(), path).ok());
    std::ifstream in(path, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes_.size(), 1000u);
  }

  fs::path write(const std::string& content, const std::string& name = "damaged.vdb") const {
    std::ofstream(folder_ / name, std::ios::binary) << content;
    return folder_ / name;
  }
  // The error of loading `content`; empty when it loads.
  std::string loadError(const std::string& content) const {
    auto r = loadMap(write(content));
    return r.ok() ? std::string() : r.error();
  }

  std::size_t payloadSize() const { return bytes_.size() - kTrailer; }

  // The sealed bytes of a plane fused with the bayes rule (its candidates in the sidecar grid).
  std::string sealedBayesMap() const {
    VolumeParams params;
    params.label_rule = LabelRule::kBayes;
    params.label_likelihood = 0.8f;
    LabeledVolume bayes(params);
    const PinholeIntrinsics k = testing::smallCamera();
    const Pose pose = testing::lookAt({0, 0, 0}, {0, 0, 1});
    const cv::Mat labels(k.height, k.width, CV_16UC1, cv::Scalar(4));
    const cv::Mat confidence(k.height, k.width, CV_32FC1, cv::Scalar(0.6));
    const cv::Mat color(k.height, k.width, CV_8UC3, cv::Scalar(10, 120, 230));
    EXPECT_TRUE(
        integrate(bayes, testing::renderPlane(k, pose, {0, 0, -1}, -1.0), color, labels, confidence, k, pose).ok());
    const fs::path path = folder_ / "bayes.vdb";
    EXPECT_TRUE(saveMap(bayes, legend(), path).ok());
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }

  static constexpr std::size_t kTrailer = 32;
  std::string bytes_;
};

TEST(MapFileCrc, OracleMatchesTheStandardCheckValue) {
  EXPECT_EQ(crc64xz("123456789"), 0x995DC9BBDF1939FAull);  // CRC-64/XZ's published check value
}

TEST_F(DamagedMapFile, TrailerSealsLengthAndCrcOfTheOpenVdbBytes) {
  const std::size_t at = payloadSize();
  EXPECT_EQ(bytes_.substr(at, 8), "SFMAPEND");
  EXPECT_EQ(littleEndianAt(bytes_, at + 8) & 0xFFFFFFFFu, 1u);  // seal version
  EXPECT_EQ(littleEndianAt(bytes_, at + 8) >> 32, 0u);          // reserved
  EXPECT_EQ(littleEndianAt(bytes_, at + 16), at);
  EXPECT_EQ(littleEndianAt(bytes_, at + 24), crc64xz(bytes_.substr(0, at)));
  EXPECT_EQ(loadError(bytes_), "");
}

TEST_F(DamagedMapFile, TruncationAtAnyPointIsRefusedBeforeOpenVdbReadsIt) {
  for (std::size_t keep :
       {std::size_t{0}, std::size_t{1}, std::size_t{31}, std::size_t{32}, std::size_t{100}, payloadSize() / 3,
        payloadSize() / 2, payloadSize() - 1, payloadSize(), payloadSize() + 8, bytes_.size() - 1}) {
    const std::string error = loadError(bytes_.substr(0, keep));
    ASSERT_NE(error, "") << "kept " << keep << " bytes";
    EXPECT_NE(error.find("damaged.vdb"), std::string::npos) << error;
    EXPECT_NE(error.find("no integrity trailer at its end (the file is truncated"), std::string::npos)
        << "kept " << keep << ": " << error;
  }
}

TEST_F(DamagedMapFile, AFlippedByteAnywhereIsRefused) {
  // About 600 positions spread over the whole file, plus every byte of the trailer.
  std::vector<std::size_t> positions;
  for (std::size_t at = 0; at < payloadSize(); at += payloadSize() / 600 + 1) positions.push_back(at);
  positions.push_back(payloadSize() - 1);
  for (std::size_t at = payloadSize(); at < bytes_.size(); ++at) positions.push_back(at);
  for (std::size_t at : positions) {
    std::string corrupt = bytes_;
    corrupt[at] = static_cast<char>(corrupt[at] ^ 0x10);
    const std::string error = loadError(corrupt);
    ASSERT_NE(error, "") << "flipped byte " << at;
    // The seal names what is wrong; OpenVDB never parsed the bytes ("not a readable OpenVDB file").
    const char* expected = at < payloadSize()        ? "CRC-64 of the map data is"
                           : at < payloadSize() + 8  ? "no integrity trailer"
                           : at < payloadSize() + 12 ? "integrity trailer version"
                           : at < payloadSize() + 16 ? "the integrity trailer is corrupt"
                           : at < payloadSize() + 24 ? "bytes were lost or added"
                                                     : "CRC-64 of the map data is";
    EXPECT_NE(error.find(expected), std::string::npos) << "flipped byte " << at << ": " << error;
  }
}

TEST_F(DamagedMapFile, AppendedBytesAreRefused) {
  const std::string error = loadError(bytes_ + "more");
  EXPECT_NE(error.find("no integrity trailer"), std::string::npos) << error;
  // A second sealed copy appended keeps a valid-looking trailer at the end; its length does not match.
  const std::string doubled = loadError(bytes_ + bytes_);
  EXPECT_NE(doubled.find("holds " + std::to_string(2 * bytes_.size() - kTrailer) +
                         " bytes of map data but its trailer records " + std::to_string(payloadSize())),
            std::string::npos)
      << doubled;
}

TEST_F(DamagedMapFile, OtherSealVersionsAreRefusedByName) {
  std::string future = bytes_;
  putLittleEndianAt(future, payloadSize() + 8, 2, 4);
  EXPECT_NE(loadError(future).find("integrity trailer version 2 is not supported (this build reads 1)"),
            std::string::npos)
      << loadError(future);
}

// A sealed map re-sealed with another format version written into its metadata. OpenVDB file
// metadata: name, type name ("int32") and value size, each length-prefixed, then the value.
std::size_t formatVersionOffset(const std::string& sealed) {
  const std::string key = "semfuse:format_version";
  return sealed.find(key) + key.size() + 4 + 5 + 4;
}
std::string withFormatVersion(const std::string& sealed, int version) {
  const std::size_t payload = sealed.size() - 32;
  std::string edited = sealed;
  putLittleEndianAt(edited, formatVersionOffset(sealed), static_cast<uint64_t>(version), 4);
  putLittleEndianAt(edited, payload + 24, crc64xz(edited.substr(0, payload)));
  return edited;
}

TEST_F(DamagedMapFile, AResealedMapWithAnotherFormatVersionIsRefusedByTheMetadataCheck) {
  const std::string key = "semfuse:format_version";
  const std::size_t name_at = bytes_.find(key);
  ASSERT_NE(name_at, std::string::npos);
  ASSERT_EQ(bytes_.substr(name_at + key.size() + 4, 5), "int32");
  ASSERT_EQ(littleEndianAt(bytes_, formatVersionOffset(bytes_)) & 0xFFFFFFFFu,
            static_cast<uint64_t>(kMapFormatVersion));
  const std::string error = loadError(withFormatVersion(bytes_, 99));
  EXPECT_NE(error.find("map format version 99 is not supported"), std::string::npos) << error;
}

TEST_F(DamagedMapFile, VersionTwoLoadsWithTheEvidenceRuleAndIsRefusedWithATopFiveRule) {
  ASSERT_EQ(labeledPlane().params().label_rule, LabelRule::kEvidence);
  EXPECT_EQ(loadError(withFormatVersion(bytes_, 2)), "");

  const std::string sealed = sealedBayesMap();
  EXPECT_EQ(loadError(sealed), "");
  const std::string error = loadError(withFormatVersion(sealed, 2));
  EXPECT_NE(error.find("map format version 2 stores the 'bayes' rule's candidates as a top-3 list"), std::string::npos)
      << error;
}

// Version 1 predates label rules: its maps were fused with the evidence rule, and load so
// whatever the default rule is now; label rule fields in a file marked version 1 are not read.
TEST_F(DamagedMapFile, VersionOneLoadsWithTheEvidenceRuleWhateverTheDefault) {
  ASSERT_EQ(VolumeParams{}.label_rule, LabelRule::kBayes);
  auto loaded = loadMap(write(withFormatVersion(sealedBayesMap(), 1)));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const VolumeParams& params = loaded.value().volume.params();
  EXPECT_EQ(loaded.value().format_version, 1);
  EXPECT_EQ(params.label_rule, LabelRule::kEvidence);
  EXPECT_EQ(params.label_likelihood, VolumeParams{}.label_likelihood);  // the file's 0.8 is not read
  EXPECT_EQ(params.voxel_size, VolumeParams{}.voxel_size);
  EXPECT_EQ(loaded.value().volume.labelSidecarGrid(), nullptr);
}

TEST_F(DamagedMapFile, NonMapFilesAreRefused) {
  const std::string text = loadError("this is not a map");
  EXPECT_NE(text.find("no integrity trailer"), std::string::npos) << text;
  auto missing = loadMap(folder_ / "nothing.vdb");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("cannot open"), std::string::npos) << missing.error();
}

// A process id that was just in use and is gone now (the child exited and was reaped).
pid_t deadProcessId() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

TEST_F(MapFile, TemporaryFilesOfDeadWritersAreRemovedOnSaveAndLoad) {
  const fs::path path = folder_ / "map.vdb";
  auto touch = [&](const std::string& name) {
    std::ofstream(folder_ / name) << "partial map";
    return folder_ / name;
  };
  const pid_t dead = deadProcessId();
  ASSERT_GT(dead, 0);
  ASSERT_NE(::kill(dead, 0), 0);
  const fs::path stale = touch(".map.vdb.tmp-" + std::to_string(dead));
  const fs::path live = touch(".map.vdb.tmp-" + std::to_string(::getppid()));  // our parent runs
  const fs::path other_map = touch(".other.vdb.tmp-" + std::to_string(dead));
  const fs::path not_a_pid = touch(".map.vdb.tmp-12ab");

  ASSERT_TRUE(saveMap(labeledPlane(), legend(), path).ok());
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other_map));
  EXPECT_TRUE(fs::exists(not_a_pid));

  // A server killed while saving, then restarted: loading its map cleans up.
  const fs::path killed = touch(".map.vdb.tmp-" + std::to_string(dead));
  ASSERT_TRUE(loadMap(path).ok());
  EXPECT_FALSE(fs::exists(killed));
  EXPECT_TRUE(fs::exists(live));

  touch(".map.vdb.tmp-" + std::to_string(dead));
  EXPECT_EQ(removeStaleTemporaries(path), std::vector<fs::path>{killed});
  EXPECT_EQ(removeStaleTemporaries(path), std::vector<fs::path>{});
  EXPECT_TRUE(fs::exists(path));
}

TEST_F(MapFile, PlainVdbFilesAreRefused) {
  const fs::path path = folder_ / "plain.vdb";
  openvdb::io::File file(path.string());
  file.write({openvdb::FloatGrid::create(1.0f)});
  file.close();
  auto r = loadMap(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("a plain OpenVDB file"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace semfuse::volume
