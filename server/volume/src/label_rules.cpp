#include "semfuse/volume/label_rules.hpp"

namespace semfuse::volume {

Result<LabelRule> parseLabelRule(const std::string& text) {
  if (text == "evidence") return LabelRule::kEvidence;
  if (text == "majority") return LabelRule::kMajority;
  if (text == "bayes") return LabelRule::kBayes;
  return makeError("unknown label rule '" + text + "' (evidence, majority or bayes)");
}

const char* labelRuleName(LabelRule rule) {
  switch (rule) {
    case LabelRule::kEvidence:
      return "evidence";
    case LabelRule::kMajority:
      return "majority";
    case LabelRule::kBayes:
      return "bayes";
  }
  return "unknown";
}

}  // namespace semfuse::volume
