#include <gtest/gtest.h>

#include "semfuse/core/legend_io.hpp"

namespace semfuse {
namespace {

void expectError(const Result<LabelLegend>& result, const std::string& fragment) {
  ASSERT_FALSE(result.ok()) << "accepted, expected an error containing: " << fragment;
  EXPECT_NE(result.error().find(fragment), std::string::npos) << result.error();
}

TEST(LegendYaml, ParsesIdsNamesColoursAndBackground) {
  auto legend = parseLegendYaml(R"(
name: kitchen
labels:
  - {id: 5, name: chair, color: [220, 40, 60]}
  - {id: 0, name: unlabeled, color: [0, 0, 0]}
  - {id: 1, name: wall}
background: [1, 0]
)");
  ASSERT_TRUE(legend.ok()) << legend.error();
  const LabelLegend& l = legend.value();
  EXPECT_EQ(l.name, "kitchen");
  ASSERT_EQ(l.labels.size(), 3u);
  EXPECT_EQ(l.labels[0].id, 0);  // sorted by id
  EXPECT_EQ(l.labels[2].name, "chair");
  EXPECT_EQ(l.labels[2].rgb, (std::array<uint8_t, 3>{220, 40, 60}));
  EXPECT_EQ(l.labels[1].rgb, LabelLegend{}.colorOf(1));  // no colour: the stable fallback
  EXPECT_EQ(l.background_ids, (std::vector<LabelId>{0, 1}));
  EXPECT_TRUE(l.isBackground(1));
}

TEST(LegendYaml, RoundTripsThroughYaml) {
  const LabelLegend original = *builtinLegend("voc");
  auto parsed = parseLegendYaml(legendToYaml(original));
  ASSERT_TRUE(parsed.ok()) << parsed.error();
  ASSERT_EQ(parsed.value().labels.size(), original.labels.size());
  for (std::size_t i = 0; i < original.labels.size(); ++i) {
    EXPECT_EQ(parsed.value().labels[i].id, original.labels[i].id);
    EXPECT_EQ(parsed.value().labels[i].name, original.labels[i].name);
    EXPECT_EQ(parsed.value().labels[i].rgb, original.labels[i].rgb);
  }
  EXPECT_EQ(parsed.value().background_ids, original.background_ids);
}

TEST(LegendYaml, EachMistakeHasItsOwnMessage) {
  expectError(parseLegendYaml("name: x\nlabels: [ {id: 1, name: a}", "l.yaml"), "l.yaml:");
  expectError(parseLegendYaml("name: x\nlabels: [ {id: 1, name: a}", "l.yaml"), "malformed YAML");
  expectError(parseLegendYaml("labels: [{id: 1, name: a}]"), "needs a 'name'");
  expectError(parseLegendYaml("name: x\nlabels: []"), "non-empty 'labels'");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 70000, name: a}]"), "label id 70000 outside [0, 65535]");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1.5, name: a}]"), "label id '1.5' is not an integer");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, name: a}, {id: 1, name: b}]"), "label id 1 appears twice");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, name: a}, {id: 2, name: a}]"), "name 'a' used by two labels");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, name: a, color: [1, 2]}]"), "must be [r, g, b]");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, name: a, color: [1, 2, 300]}]"), "colour channel 300");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, name: a}]\nbackground: [3]"),
              "background id 3 is not a label");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, nme: a}]"), "unknown label key 'nme'");
  expectError(parseLegendYaml("name: x\nlabel: [{id: 1, name: a}]"), "unknown key 'label'");
  // Found by fuzz/targets/legend_yaml.cpp: these used to throw or to be accepted.
  expectError(parseLegendYaml("{[1]: x}", "k.yaml"), "k.yaml:1:2: keys must be plain names");
  expectError(parseLegendYaml("name: x\nlabels: [{[id]: 1, name: a}]"), "label keys must be plain names");
  expectError(parseLegendYaml("name: x\nlabels: [{id: 1, name: \"wall\\nfloor\"}]"),
              "the name of label 1 has a control character at byte 4");
  expectError(parseLegendYaml("name: k\xe4\nlabels: [{id: 1, name: a}]"), "legend name is not valid UTF-8 at byte 1");
  // Well-formed UTF-8 only: an overlong 'O' (C1 8F), a UTF-16 surrogate and a code point past U+10FFFF.
  // The overlong one was found by the fuzzer: yaml-cpp wrote it back as a different name.
  expectError(parseLegendYaml("name: x\nlabels: [{id: 3, name: \"a\xc1\x8ftable\"}]"),
              "the name of label 3 is not valid UTF-8 at byte 1");
  expectError(parseLegendYaml("name: \"x\xed\xa0\x80\"\nlabels: [{id: 1, name: a}]"),
              "legend name is not valid UTF-8 at byte 1");
  expectError(parseLegendYaml("name: \"x\xf4\x90\x80\x80\"\nlabels: [{id: 1, name: a}]"),
              "legend name is not valid UTF-8 at byte 1");
  EXPECT_TRUE(parseLegendYaml("name: \"\xf0\x9f\x8d\xb4 \xe2\x82\xac\"\nlabels: [{id: 1, name: a}]").ok());
  expectError(parseLegendYaml("name: x\nlabels: [{name: a}]", "m.yaml"), "m.yaml: label id must be an integer");
  EXPECT_TRUE(parseLegendYaml("name: k\u00fcche\nlabels: [{id: 1, name: \"\u6905\u5b50\"}]").ok());
}

TEST(LegendYaml, ResolveTakesBuiltinNamesOrFiles) {
  auto builtin = resolveLegend("nyu40");
  ASSERT_TRUE(builtin.ok());
  EXPECT_EQ(builtin.value().labels.size(), 41u);
  expectError(resolveLegend("/nonexistent/legend.yaml"), "neither a built-in legend (ade20k, nyu40, synthetic, voc)");
}

}  // namespace
}  // namespace semfuse
