#include <gtest/gtest.h>

#include "semfuse/segmentation/label_map.hpp"

namespace semfuse::segmentation {
namespace {

TEST(LabelMap, ParsesPairsAndLeavesUnlistedClassesUnlabeled) {
  auto map = parseLabelMap("# VOC -> synthetic\n9 5   # chair\n\n11 4\n", 21, "test");
  ASSERT_TRUE(map.ok()) << map.error();
  ASSERT_EQ(map.value().size(), 21u);
  EXPECT_EQ(map.value()[9], 5);
  EXPECT_EQ(map.value()[11], 4);
  EXPECT_EQ(map.value()[0], 0);
  EXPECT_EQ(map.value()[15], 0);
}

TEST(LabelMap, RejectsMalformedLinesWithTheirLineNumber) {
  auto out_of_range = parseLabelMap("1 1\n21 3\n", 21, "map.txt");
  ASSERT_FALSE(out_of_range.ok());
  EXPECT_NE(out_of_range.error().find("map.txt:2"), std::string::npos) << out_of_range.error();
  EXPECT_FALSE(parseLabelMap("3\n", 21, "m").ok());
  EXPECT_FALSE(parseLabelMap("3 4 5\n", 21, "m").ok());
  EXPECT_FALSE(parseLabelMap("3 70000\n", 21, "m").ok());
}

TEST(LabelMap, IdentityMapsEachClassToItself) {
  const LabelMap map = identityLabelMap(150);
  EXPECT_EQ(map[0], 0);
  EXPECT_EQ(map[149], 149);
}

}  // namespace
}  // namespace semfuse::segmentation
