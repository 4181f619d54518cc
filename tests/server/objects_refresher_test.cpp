// Objects kept up to date in the background (server/core/src/objects_refresher.*) and the objects
// query's max age (service_handlers.hpp): on the fuzzers' map of two labeled walls, which then
// grows a third wall behind the camera. The waits are for conditions, never for the clock.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>

#include <opencv2/core.hpp>

#include "eventually.hpp"
#include "map_access.hpp"
#include "objects_refresher.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/volume/integrator.hpp"
#include "service_handlers.hpp"
#include "tiny_map.hpp"

namespace semfuse::server {
namespace {

using semfuse::testing::eventually;

constexpr LabelId kThirdWall = 15;

// A map whose snapshot a test replaces, as the server's grows.
class RefresherTestMap final : public MapAccess {
 public:
  explicit RefresherTestMap(std::shared_ptr<const volume::LabeledVolume> volume)
      : volume_(std::move(volume)), legend_(*builtinLegend("voc")) {}
  void read(const std::function<void(const volume::LabeledVolume&)>& fn) const override { fn(*snapshot()); }
  std::shared_ptr<const volume::LabeledVolume> snapshot() const override {
    std::lock_guard lock(mutex_);
    return volume_;
  }
  const LabelLegend& legend() const override { return legend_; }
  void grow(std::shared_ptr<const volume::LabeledVolume> volume) {
    std::lock_guard lock(mutex_);
    volume_ = std::move(volume);
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const volume::LabeledVolume> volume_;
  LabelLegend legend_;
};

// The two walls' map and, from a copy of it (revisions go on), the same with a wall of label 15
// 1 m behind the camera.
std::shared_ptr<const volume::LabeledVolume> refresherTwoWalls() {
  return std::make_shared<const volume::LabeledVolume>(fuzz::makeTinyMap());
}
std::shared_ptr<const volume::LabeledVolume> refresherThirdWall(const volume::LabeledVolume& two_walls) {
  auto grown = std::make_shared<volume::LabeledVolume>(two_walls.deepCopy());
  const int w = 32, h = 24;
  const PinholeIntrinsics k{w, h, 20.0, 20.0, (w - 1) / 2.0, (h - 1) / 2.0};
  cv::Mat depth(h, w, CV_32FC1, cv::Scalar(1.0f)), labels(h, w, CV_16UC1, cv::Scalar(kThirdWall));
  cv::Mat confidence(h, w, CV_32FC1, cv::Scalar(0.9f)), color(h, w, CV_8UC3, cv::Scalar(90, 90, 90));
  Pose behind = Pose::Identity();
  behind.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()));
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(volume::integrate(*grown, depth, color, labels, confidence, k, behind).ok());
  return grown;
}

ObjectsRequest refresherRequest(double max_age_s) {
  ObjectsRequest request;
  request.min_voxels = 1;
  request.max_age_s = max_age_s;
  return request;
}

std::size_t refresherObjects(const objects::ObjectSet& set) {
  std::size_t n = 0;
  for (const auto& object : set.objects) n += object.fragment ? 0 : 1;
  return n;
}

TEST(ObjectsMaxAge, TakesTheLatestSetWhileItIsYoungEnoughElseGroupsTheMapAsItIs) {
  RefresherTestMap map(refresherTwoWalls());
  auto tracker = makeObjectTracker(map.legend(), map.snapshot()->voxelSize());
  auto first = handleObjects(refresherRequest(0.0), map, *tracker);
  ASSERT_TRUE(first.ok()) << first.message;
  ASSERT_EQ(first.value.size(), 2u);

  map.grow(refresherThirdWall(*map.snapshot()));
  // An hour will do: the set of the two walls, grouped before the map grew.
  auto recent = handleObjects(refresherRequest(3600.0), map, *tracker);
  ASSERT_TRUE(recent.ok()) << recent.message;
  ASSERT_EQ(recent.value.size(), 2u);
  EXPECT_EQ(recent.value[0].id, first.value[0].id);
  // The map as it is: three walls, the first two with their ids.
  auto now = handleObjects(refresherRequest(0.0), map, *tracker);
  ASSERT_TRUE(now.ok()) << now.message;
  ASSERT_EQ(now.value.size(), 3u);
  std::size_t kept = 0, third = 0;
  for (const ObjectInstance& o : now.value) {
    kept += o.id == first.value[0].id || o.id == first.value[1].id;
    third += o.label == kThirdWall;
  }
  EXPECT_EQ(kept, 2u);
  EXPECT_EQ(third, 1u);

  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    auto refused = handleObjects(refresherRequest(bad), map, *tracker);
    EXPECT_EQ(refused.code, ReplyCode::kInvalidArgument) << bad;
    EXPECT_EQ(refused.message, "max_age must be 0 or more seconds");
  }
}

TEST(ObjectsRefresher, KeepsTheObjectsUpToDateWhileTheMapGrows) {
  RefresherTestMap map(refresherTwoWalls());
  auto tracker = makeObjectTracker(map.legend(), map.snapshot()->voxelSize());
  ObjectsRefresher refresher(map, *tracker, /*rate_hz=*/50.0, [] { return false; });
  refresher.touch();  // as an objects query does
  ASSERT_TRUE(eventually([&] { return tracker->latest().set != nullptr; }));
  EXPECT_EQ(refresherObjects(*tracker->latest().set), 2u);

  map.grow(refresherThirdWall(*map.snapshot()));
  ASSERT_TRUE(eventually([&] { return refresherObjects(*tracker->latest().set) == 3; }));
  // A query that accepts a minute-old answer gets the refreshed set.
  auto reply = handleObjects(refresherRequest(60.0), map, *tracker);
  ASSERT_TRUE(reply.ok()) << reply.message;
  EXPECT_EQ(reply.value.size(), 3u);
}

TEST(ObjectsRefresher, GroupsNothingUntilSomebodyWantsObjects) {
  RefresherTestMap map(refresherTwoWalls());
  auto tracker = makeObjectTracker(map.legend(), map.snapshot()->voxelSize());
  std::atomic<int> rounds{0};
  std::atomic<bool> reader{false};
  ObjectsRefresher refresher(map, *tracker, /*rate_hz=*/50.0, [&] {
    ++rounds;
    return reader.load();
  });
  // Five rounds asked whether anybody listens, and nobody did: no objects were grouped.
  ASSERT_TRUE(eventually([&] { return rounds.load() >= 5; }));
  EXPECT_EQ(tracker->latest().set, nullptr);
  reader = true;  // a reader of the object events came
  ASSERT_TRUE(eventually([&] { return tracker->latest().set != nullptr; }));
  EXPECT_EQ(refresherObjects(*tracker->latest().set), 2u);
}

}  // namespace
}  // namespace semfuse::server
