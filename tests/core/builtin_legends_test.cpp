#include <set>

#include <gtest/gtest.h>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/legend_io.hpp"

namespace semfuse {
namespace {

std::string nameOf(const LabelLegend& legend, LabelId id) {
  const LabelInfo* info = legend.find(id);
  return info ? info->name : "<missing>";
}

TEST(BuiltinLegends, NamesAreListed) {
  EXPECT_EQ(builtinLegendNames(), (std::vector<std::string>{"ade20k", "nyu40", "synthetic", "voc"}));
  EXPECT_FALSE(builtinLegend("coco").has_value());
}

TEST(BuiltinLegends, Ade20kIsObjectInfo150ShiftedByOne) {
  const LabelLegend legend = *builtinLegend("ade20k");
  ASSERT_EQ(legend.labels.size(), 151u);
  EXPECT_EQ(nameOf(legend, 0), "other");
  EXPECT_EQ(nameOf(legend, 1), "wall");
  EXPECT_EQ(nameOf(legend, 4), "floor");
  EXPECT_EQ(nameOf(legend, 6), "ceiling");
  EXPECT_EQ(nameOf(legend, 11), "cabinet");
  EXPECT_EQ(nameOf(legend, 16), "table");
  EXPECT_EQ(nameOf(legend, 20), "chair");
  EXPECT_EQ(nameOf(legend, 24), "sofa");
  EXPECT_EQ(nameOf(legend, 51), "refrigerator");
  EXPECT_EQ(nameOf(legend, 150), "flag");
  EXPECT_EQ(legend.maxId(), 150);
}

TEST(BuiltinLegends, VocAndNyu40) {
  const LabelLegend voc = *builtinLegend("voc");
  ASSERT_EQ(voc.labels.size(), 21u);
  EXPECT_EQ(nameOf(voc, 0), "background");
  EXPECT_EQ(nameOf(voc, 9), "chair");
  EXPECT_EQ(nameOf(voc, 11), "diningtable");
  EXPECT_EQ(nameOf(voc, 18), "sofa");
  EXPECT_EQ(nameOf(voc, 20), "tvmonitor");
  EXPECT_TRUE(voc.isBackground(0));
  EXPECT_FALSE(voc.isBackground(9));

  const LabelLegend nyu = *builtinLegend("nyu40");
  ASSERT_EQ(nyu.labels.size(), 41u);
  EXPECT_EQ(nameOf(nyu, 0), "unlabeled");
  EXPECT_EQ(nameOf(nyu, 1), "wall");
  EXPECT_EQ(nameOf(nyu, 5), "chair");
  EXPECT_EQ(nameOf(nyu, 22), "ceiling");
  EXPECT_EQ(nameOf(nyu, 40), "otherprop");
}

TEST(BuiltinLegends, SyntheticIdsAreTheContractWithTheSyntheticScene) {
  const LabelLegend legend = *builtinLegend("synthetic");
  const std::vector<std::string> expected = {"unlabeled", "floor", "wall",   "ceiling", "table",
                                             "chair",     "box",   "sphere", "cabinet"};
  ASSERT_EQ(legend.labels.size(), expected.size());
  for (std::size_t id = 0; id < expected.size(); ++id)
    EXPECT_EQ(nameOf(legend, static_cast<LabelId>(id)), expected[id]);
}

TEST(BuiltinLegends, AllValidWithDistinctColours) {
  for (const std::string& name : builtinLegendNames()) {
    const LabelLegend legend = *builtinLegend(name);
    EXPECT_EQ(legend.name, name);
    const Status valid = validateLegend(legend);
    EXPECT_TRUE(valid.ok()) << valid.error();
    std::set<std::array<uint8_t, 3>> colours;
    for (const LabelInfo& label : legend.labels) colours.insert(label.rgb);
    EXPECT_EQ(colours.size(), legend.labels.size()) << name;
    EXPECT_EQ(legend.background_ids, std::vector<LabelId>{0}) << name;
  }
}

}  // namespace
}  // namespace semfuse
