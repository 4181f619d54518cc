// The packed 8-byte voxel: exact round trips of representable values, and all-zero = unobserved.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "semfuse/volume/labeled_volume.hpp"
#include "semfuse/volume/voxel.hpp"

namespace semfuse::volume {
namespace {

TEST(Voxel, PacksIntoEightBytes) {
  static_assert(sizeof(PackedVoxel) == 8);
  EXPECT_EQ(sizeof(GeometryGrid::ValueType), 8u);
}

TEST(Voxel, RoundTripsHalfRepresentableValues) {
  const VoxelValue v{-0.03125f, 17.0f, 4242, 3.5f};
  const VoxelValue back = unpackVoxel(packVoxel(v));
  EXPECT_EQ(back.tsdf, v.tsdf);
  EXPECT_EQ(back.weight, v.weight);
  EXPECT_EQ(back.label, v.label);
  EXPECT_EQ(back.score, v.score);
}

TEST(Voxel, KeepsTsdfToAFewMicrometres) {
  for (float tsdf : {0.0399f, -0.0123f, 0.0001f}) EXPECT_NEAR(unpackTsdf(packVoxel(tsdf, 1, 0, 0)), tsdf, 3e-5f);
}

TEST(Voxel, NegativeScoreAndMaxLabelSurvive) {
  const PackedVoxel p = packVoxel(0.01f, 2.0f, 65535, -0.25f);
  EXPECT_EQ(unpackLabel(p), 65535);
  EXPECT_EQ(unpackScore(p), -0.25f);
  EXPECT_EQ(unpackWeight(p), 2.0f);
}

TEST(Voxel, ZeroBitsAreTheUnobservedVoxel) {
  EXPECT_FALSE(isObserved(kUnobservedVoxel));
  EXPECT_FALSE(unpackVoxel(kUnobservedVoxel).observed());
  EXPECT_EQ(unpackLabel(kUnobservedVoxel), kUnlabeled);
  EXPECT_TRUE(isObserved(packVoxel(0.0f, 1.0f, 0, 0.0f)));
  EXPECT_FALSE(isObserved(packVoxel(0.02f, 0.0f, 3, 1.0f)));
}

// The packing uses its own table-free half conversions; they must give the bits of
// openvdb::math::half (IEEE binary16, round to nearest even) for every input that matters.
TEST(Voxel, HalfConversionsMatchOpenVdbHalfExactly) {
  for (uint32_t h = 0; h <= 0xFFFFu; ++h) {
    openvdb::math::half reference;
    reference.setBits(static_cast<unsigned short>(h));
    const float expected = static_cast<float>(reference);
    const float got = detail::halfValue(h);
    if (std::isnan(expected)) {
      ASSERT_TRUE(std::isnan(got)) << "half bits " << h;
      ASSERT_TRUE(std::isnan(detail::halfValueBranchless(h))) << "half bits " << h;
      continue;
    }
    ASSERT_EQ(detail::floatBits(got), detail::floatBits(expected)) << "half bits " << h;
    ASSERT_EQ(detail::floatBits(detail::halfValueBranchless(h)), detail::floatBits(expected)) << "half bits " << h;
    ASSERT_EQ(detail::halfBits(got), h) << "half bits " << h;  // every half round-trips
  }
  // Floats: every 1021st bit pattern (all exponents, mixed mantissas) plus the rounding ties.
  auto check = [](float f) {
    const uint16_t expected = openvdb::math::half(f).bits();
    if (std::isnan(f)) {
      ASSERT_TRUE(std::isnan(detail::halfValue(detail::halfBits(f))));
      return;
    }
    ASSERT_EQ(detail::halfBits(f), expected) << "float " << f << " bits " << detail::floatBits(f);
  };
  for (uint64_t u = 0; u <= 0xFFFFFFFFull; u += 1021) check(detail::bitsFloat(static_cast<uint32_t>(u)));
  for (uint32_t h = 0; h < 0x7C00u; ++h) {  // exactly halfway between two halves, both signs
    const float lo = detail::halfValue(h), hi = detail::halfValue(h + 1);
    const float mid = detail::bitsFloat((detail::floatBits(lo) + detail::floatBits(hi)) / 2);
    check(mid);
    check(-mid);
  }
}

TEST(Voxel, ColorRoundTrips) {
  const Rgb8 c{12, 200, 255};
  EXPECT_EQ(unpackColor(packColor(c)), c);
}

TEST(VolumeParams, RejectsNonsenseWithAReason) {
  VolumeParams p;
  EXPECT_TRUE(p.validate().ok());
  p.voxel_size = 0;
  EXPECT_NE(p.validate().error().find("voxel_size"), std::string::npos);
  p = {};
  p.truncation = 0.005;
  EXPECT_NE(p.validate().error().find("truncation"), std::string::npos);
  p = {};
  p.max_weight = 5000;
  EXPECT_NE(p.validate().error().find("max_weight"), std::string::npos);
  p = {};
  p.max_label_score = -1;
  EXPECT_NE(p.validate().error().find("max_label_score"), std::string::npos);
  p = {};
  p.min_depth = 3;
  p.max_depth = 2;
  EXPECT_NE(p.validate().error().find("depth range"), std::string::npos);
  EXPECT_FALSE(LabeledVolume::create(p).ok());
}

TEST(LabeledVolume, MapsVoxelCentresToWorld) {
  VolumeParams p;
  p.voxel_size = 0.02;
  const LabeledVolume volume(p);
  EXPECT_EQ(volume.worldToIndex({0.031, -0.029, 0.0}), openvdb::Coord(2, -1, 0));
  EXPECT_TRUE(volume.indexToWorld({3, -4, 5}).isApprox(Eigen::Vector3d(0.06, -0.08, 0.10)));
  EXPECT_EQ(volume.allocatedVoxels(), 0u);
  EXPECT_FALSE(volume.voxelAt({1, 2, 3}).observed());
}

}  // namespace
}  // namespace semfuse::volume
