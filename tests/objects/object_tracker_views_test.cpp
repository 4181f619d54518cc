// The objects' frames through ObjectTracker: the synthetic room fused from 30 frames of its orbit
// at 4 cm. Frames recorded after the objects were grouped show up on the same snapshot without a
// regrouping (the server records a frame's view just after integrating it, so a query can come
// in between), and forgetting the views empties them.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "semfuse/objects/object_tracker.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::objects {
namespace {

constexpr int kFrames = 30;

class ObjectTrackerViews : public ::testing::Test {
 protected:
  ObjectTrackerViews() {
    config_.intrinsics = config_.intrinsics.scaled(0.25);
    config_.trajectory.frame_count = kFrames;
    sequence_ = std::make_unique<synthetic::SyntheticSequence>(config_);
    params_.voxel_size = 0.04;
    params_.truncation = 0.16;
    params_.integrate_color = false;
    auto created = volume::LabeledVolume::create(params_);
    EXPECT_TRUE(created.ok()) << created.error();
    auto map = std::make_shared<volume::LabeledVolume>(std::move(created).value());
    for (int i = 0; i < kFrames; ++i) {
      auto both = sequence_->frameWithGroundTruth(i);
      EXPECT_TRUE(both.ok()) << both.error();
      frames_.push_back(both.value().first);
      const Segmentation& labels = both.value().second;
      auto stats = volume::integrate(*map, frames_.back().depth, cv::Mat(), labels.labels, labels.confidence,
                                     frames_.back().intrinsics, sequence_->pose(i));
      EXPECT_TRUE(stats.ok()) << stats.error();
    }
    map_ = std::move(map);
  }

  const TrackedObject* table(const ObjectSet& set) const {
    auto found = std::find_if(set.objects.begin(), set.objects.end(), [](const TrackedObject& o) {
      return !o.fragment && o.label == synthetic::labels::kTable;
    });
    return found == set.objects.end() ? nullptr : &*found;
  }

  synthetic::SequenceConfig config_;
  std::unique_ptr<synthetic::SyntheticSequence> sequence_;
  volume::VolumeParams params_;
  std::vector<Frame> frames_;
  std::shared_ptr<const volume::LabeledVolume> map_;
};

TEST_F(ObjectTrackerViews, FramesRecordedAfterTheGroupingShowUpOnTheSameSnapshot) {
  ObjectTracker tracker(ObjectParams{}, *builtinLegend("synthetic"), params_.voxel_size);
  const auto before = tracker.objectsOf(map_);
  const TrackedObject* t = table(*before);
  ASSERT_NE(t, nullptr);
  EXPECT_TRUE(t->frames.empty());
  EXPECT_EQ(t->frame_count, 0u);
  const uint64_t update = before->update;

  for (int i = 0; i < kFrames; ++i)
    tracker.recordView(frames_[static_cast<std::size_t>(i)], sequence_->pose(i), params_.min_depth, params_.max_depth);
  const auto after = tracker.objectsOf(map_);
  EXPECT_EQ(after->update, update);  // not regrouped: the same objects, the same ids
  ASSERT_EQ(after->objects.size(), before->objects.size());
  const TrackedObject* seen = table(*after);
  ASSERT_NE(seen, nullptr);
  EXPECT_EQ(seen->id, t->id);
  // The orbit keeps the table in view: every frame saw some of it.
  EXPECT_EQ(seen->frame_count, static_cast<uint32_t>(kFrames));
  EXPECT_EQ(seen->frames.size(), ObjectTracker::kFramesPerObject);
  for (const FrameRef& f : seen->frames) {
    EXPECT_EQ(f.camera_id, frames_[0].camera_id);
    EXPECT_LT(f.seq, static_cast<uint64_t>(kFrames));
  }
  EXPECT_EQ(tracker.objectsOf(map_), after);  // nothing recorded since: the same answer

  tracker.forgetViews();
  const auto forgotten = tracker.objectsOf(map_);
  const TrackedObject* none = table(*forgotten);
  ASSERT_NE(none, nullptr);
  EXPECT_TRUE(none->frames.empty());
  EXPECT_EQ(none->frame_count, 0u);
}

}  // namespace
}  // namespace semfuse::objects
