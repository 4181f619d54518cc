// The late label passes' share of the fusion thread while frames wait: half the integrations'
// time on average, never saved up beyond one integration, and everything when no frame waits.
#include <chrono>

#include <gtest/gtest.h>

#include "label_pass_budget.hpp"

namespace semfuse {
namespace {

using std::chrono::milliseconds;

TEST(LabelPassBudget, WhileFramesWaitPassesGetHalfTheIntegrationsTime) {
  LabelPassBudget budget;
  EXPECT_FALSE(budget.allows(true));  // nothing earned yet
  // 100 integrations of 20 ms with 15 ms passes queued behind each: the passes may take 1,000 ms,
  // half of the 2,000 the integrations took, give or take the one pass that overdraws.
  milliseconds passing{0};
  for (int i = 0; i < 100; ++i) {
    budget.earn(milliseconds(20));
    while (budget.allows(true)) {
      budget.spend(true, milliseconds(15));
      passing += milliseconds(15);
    }
  }
  EXPECT_GE(passing.count(), 1000 - 15);
  EXPECT_LE(passing.count(), 1000 + 15);
}

TEST(LabelPassBudget, CreditIsNotSavedUpBeyondOneIntegration) {
  LabelPassBudget budget;
  for (int i = 0; i < 10; ++i) budget.earn(milliseconds(20));  // no pass queued meanwhile
  EXPECT_EQ(budget.credit(), milliseconds(20));
}

TEST(LabelPassBudget, WithNoFrameWaitingEveryPassRunsAndNothingIsKept) {
  LabelPassBudget budget;
  budget.earn(milliseconds(20));
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(budget.allows(false));
    budget.spend(false, milliseconds(15));
  }
  EXPECT_EQ(budget.credit(), milliseconds(0));
  EXPECT_FALSE(budget.allows(true));  // frames wait again: a new integration must earn first
}

}  // namespace
}  // namespace semfuse
