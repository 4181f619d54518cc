#pragma once
// Locates ../shared (the 7-Scenes frames and models) for tests and benchmarks: $SEMFUSE_SHARED,
// else the folder beside the source tree. Missing data skips a test on a developer machine but
// fails it in CI (CI=true), where it must be present.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace semfuse::testing {

inline std::filesystem::path sharedDir() {
  if (const char* env = std::getenv("SEMFUSE_SHARED"); env && *env) return env;
  return std::filesystem::path(SEMFUSE_SOURCE_DIR) / ".." / "shared";
}

inline std::filesystem::path redkitchenDir() { return sharedDir() / "data" / "7scenes-redkitchen"; }

inline bool runningInCi() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

}  // namespace semfuse::testing

// Use at the top of a test body: skips (developer machine) or fails (CI) without the data.
#define SEMFUSE_REQUIRE_SHARED_DIR(path)                                              \
  do {                                                                                \
    if (!std::filesystem::exists(path)) {                                             \
      if (::semfuse::testing::runningInCi())                                          \
        FAIL() << "shared data missing in CI: " << (path) << " (set SEMFUSE_SHARED)"; \
      GTEST_SKIP() << "shared data not found: " << (path) << " (set SEMFUSE_SHARED)"; \
    }                                                                                 \
  } while (0)
