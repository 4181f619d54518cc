// Fuzz target: a label legend YAML file (--legend FILE on every program) -> parseLegendYaml.
// A legend that parses must be valid, and must read back unchanged from legendToYaml.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "semfuse/core/legend_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto legend = semfuse::parseLegendYaml(text, "fuzz.yaml");
  if (!legend) return 0;
  SEMFUSE_FUZZ_CHECK(semfuse::validateLegend(legend.value()).ok());
  auto again = semfuse::parseLegendYaml(semfuse::legendToYaml(legend.value()), "round-trip.yaml");
  SEMFUSE_FUZZ_CHECK(again.ok());
  const semfuse::LabelLegend& a = legend.value();
  const semfuse::LabelLegend& b = again.value();
  SEMFUSE_FUZZ_CHECK(a.name == b.name && a.background_ids == b.background_ids && a.labels.size() == b.labels.size());
  for (std::size_t i = 0; i < a.labels.size(); ++i) {
    SEMFUSE_FUZZ_CHECK(a.labels[i].id == b.labels[i].id && a.labels[i].name == b.labels[i].name &&
                       a.labels[i].rgb == b.labels[i].rgb);
  }
  return 0;
}
