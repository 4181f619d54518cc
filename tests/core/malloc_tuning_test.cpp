// keepScratchResident() (malloc_tuning.hpp): a query's scratch, freed and taken again query after
// query, no longer comes back from the kernel page by page. Its own process: the setting is
// process-wide, and the untuned baseline must be measured before it.
#include <sys/resource.h>

#include <cstddef>
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "semfuse/core/malloc_tuning.hpp"

namespace semfuse {
namespace {

// About what a raycast of the 7-Scenes map takes: the copy of the leaves in view, the TSDF
// bricks, the images, the bounds, the regions (MiB).
constexpr std::size_t kBlockMiB[] = {22, 14, 5, 4, 1};
constexpr long scratchPages() {  // of 4 KiB
  long mib = 0;
  for (std::size_t block : kBlockMiB) mib += static_cast<long>(block);
  return mib * 256;
}
constexpr long kScratchPages = scratchPages();
constexpr int kQueries = 4;

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

// Minor page faults of the last of kQueries "queries", each allocating, filling and freeing the
// blocks, on a thread of its own as the raycast service runs (glibc gives such threads their own
// malloc arena): the steady state, once glibc has adapted what it can.
long faultsPerQueryInSteadyState() {
  long faults = 0;
  std::thread([&] {
    for (int query = 0; query < kQueries; ++query) {
      const long before = minorFaults();
      std::vector<std::unique_ptr<char[]>> blocks;
      for (std::size_t mib : kBlockMiB) {
        blocks.emplace_back(new char[mib << 20]);
        std::memset(blocks.back().get(), 1, mib << 20);
        asm volatile("" : : "r"(blocks.back().get()) : "memory");  // keep the writes
      }
      blocks.clear();
      faults = minorFaults() - before;
    }
  }).join();
  return faults;
}

TEST(MallocTuning, FreedScratchIsReusedWithoutPageFaults) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "glibc only";
#endif
  // Untuned, glibc maps the largest blocks, or trims the freed ones off its heap: every query
  // faults its scratch in again.
  const long untuned = faultsPerQueryInSteadyState();
  EXPECT_GT(untuned, kScratchPages / 2) << "the untuned baseline should fault the scratch in again";

  ASSERT_TRUE(keepScratchResident());
  const long tuned = faultsPerQueryInSteadyState();
  RecordProperty("faults_per_query_untuned", static_cast<int>(untuned));
  RecordProperty("faults_per_query_tuned", static_cast<int>(tuned));
  EXPECT_LT(tuned, kScratchPages / 20) << "untuned: " << untuned << " faults per query";
}

}  // namespace
}  // namespace semfuse
