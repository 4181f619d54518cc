// The metrics of semfuse-eval on hand-made volumes and images.
#include <gtest/gtest.h>

#include "label_metric.hpp"

namespace semfuse::eval {
namespace {
using volume::LabeledVolume;
using volume::packVoxel;

// A column of voxels along z at x = y = 0 with the given TSDF values (metres) and labels,
// observed with weight 1; everything else unobserved.
LabeledVolume column(const std::vector<float>& tsdf, const std::vector<LabelId>& labels) {
  LabeledVolume volume;
  auto accessor = volume.mutableGeometryGrid().getAccessor();
  for (std::size_t z = 0; z < tsdf.size(); ++z)
    accessor.setValueOn(openvdb::Coord(0, 0, static_cast<int>(z)), packVoxel(tsdf[z], 1.0f, labels[z], 1.0f));
  return volume;
}

TEST(SurfaceVoxels, AreTheObservedVoxelsBesideASignChange) {
  const LabeledVolume volume = column({0.03f, 0.01f, -0.01f, -0.03f}, {1, 1, 1, 1});
  const auto surface = surfaceVoxels(volume);
  ASSERT_EQ(surface.size(), 2u);
  EXPECT_EQ(surface[0], openvdb::Coord(0, 0, 1));
  EXPECT_EQ(surface[1], openvdb::Coord(0, 0, 2));
}

TEST(SurfaceVoxels, UnobservedNeighboursDoNotMakeASurface) {
  LabeledVolume volume = column({0.01f, 0.02f}, {1, 1});
  // An allocated but unobserved (weight 0) voxel with a negative TSDF next to the column.
  volume.mutableGeometryGrid().getAccessor().setValueOn(openvdb::Coord(0, 0, 2), packVoxel(-0.01f, 0.0f, 0, 0.0f));
  EXPECT_TRUE(surfaceVoxels(volume).empty());
}

TEST(VolumetricLabelError, CountsDifferingLabelsWhereTheReferenceHasOne) {
  const LabeledVolume reference = column({0.03f, 0.01f, -0.01f, -0.01f, 0.01f}, {1, 4, 0, 6, 6});
  const LabeledVolume test = column({0.03f, 0.01f, -0.01f, -0.01f, 0.01f}, {1, 5, 9, 6, 0});
  const auto surface = surfaceVoxels(reference);  // z = 1, 2, 3, 4
  ASSERT_EQ(surface.size(), 4u);
  const LabelError error = volumetricLabelError(reference, test, surface);
  EXPECT_EQ(error.compared, 3u);  // z = 2 is unlabeled in the reference: not compared
  EXPECT_EQ(error.wrong, 2u);     // z = 1 (4 vs 5) and z = 4 (unlabeled counts as wrong)
  EXPECT_DOUBLE_EQ(error.fraction(), 2.0 / 3.0);
  EXPECT_EQ(volumetricLabelError(reference, reference, surface).wrong, 0u);
  EXPECT_EQ(LabelError{}.fraction(), 0.0);  // nothing to compare is no error
}

TEST(PixelLabelError, ComparesWhereTheReferenceLabels) {
  const cv::Mat reference = (cv::Mat_<uint16_t>(2, 2) << 1, 0, 2, 2);
  const cv::Mat labels = (cv::Mat_<uint16_t>(2, 2) << 1, 5, 3, 2);
  auto error = pixelLabelError(reference, labels);
  ASSERT_TRUE(error.ok()) << error.error();
  EXPECT_EQ(error.value().compared, 3u);
  EXPECT_EQ(error.value().wrong, 1u);
}

TEST(PixelLabelError, RefusesMismatchedImages) {
  const cv::Mat reference(2, 2, CV_16UC1, cv::Scalar(1));
  auto size = pixelLabelError(reference, cv::Mat(3, 2, CV_16UC1, cv::Scalar(1)));
  ASSERT_FALSE(size.ok());
  EXPECT_NE(size.error().find("2x3"), std::string::npos) << size.error();
  EXPECT_FALSE(pixelLabelError(reference, cv::Mat(2, 2, CV_8UC1, cv::Scalar(1))).ok());
}

}  // namespace
}  // namespace semfuse::eval
