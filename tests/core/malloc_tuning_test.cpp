// keepScratchResident() (malloc_tuning.hpp): a query's scratch, freed and taken again, no longer
// comes back from the kernel page by page. Its own process: the setting is process-wide.
#include <sys/resource.h>

#include <cstddef>
#include <cstring>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "semfuse/core/malloc_tuning.hpp"

namespace semfuse {
namespace {

constexpr std::size_t kScratchBytes = std::size_t{24} << 20;  // a raycast's copy of the leaves in view
constexpr long kScratchPages = static_cast<long>(kScratchBytes / 4096);

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

// Minor page faults of allocating, filling and freeing the scratch once more, after a first
// round that left glibc whatever it keeps. Run on a thread of its own, as the raycast service
// does (glibc gives such threads their own malloc arena).
long faultsOfSecondRound() {
  long faults = 0;
  std::thread([&] {
    auto round = [] {
      std::unique_ptr<char[]> scratch(new char[kScratchBytes]);
      std::memset(scratch.get(), 1, kScratchBytes);
      asm volatile("" : : "r"(scratch.get()) : "memory");  // keep the writes
    };
    round();
    const long before = minorFaults();
    round();
    faults = minorFaults() - before;
  }).join();
  return faults;
}

TEST(MallocTuning, FreedScratchIsReusedWithoutPageFaults) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "glibc only";
#endif
  // Untuned, glibc maps a block this large and unmaps it when freed: every page faults again.
  const long untuned = faultsOfSecondRound();
  EXPECT_GT(untuned, kScratchPages / 2) << "the baseline should fault the scratch in again";

  ASSERT_TRUE(keepScratchResident());
  faultsOfSecondRound();  // a fresh thread may start a fresh arena: let it take the scratch once
  const long tuned = faultsOfSecondRound();
  RecordProperty("faults_untuned", static_cast<int>(untuned));
  RecordProperty("faults_tuned", static_cast<int>(tuned));
  EXPECT_LT(tuned, kScratchPages / 20) << "untuned: " << untuned << " faults";
}

}  // namespace
}  // namespace semfuse
