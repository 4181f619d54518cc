#include <cstdlib>

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "semfuse/core/logging.hpp"

namespace semfuse {
namespace {

TEST(Logging, ParsesEveryLevelName) {
  EXPECT_EQ(parseLogLevel("debug").value(), spdlog::level::debug);
  EXPECT_EQ(parseLogLevel("WARNING").value(), spdlog::level::warn);
  EXPECT_EQ(parseLogLevel("err").value(), spdlog::level::err);
  EXPECT_EQ(parseLogLevel("off").value(), spdlog::level::off);
  auto bad = parseLogLevel("loud");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "unknown log level 'loud' (use one of trace, debug, info, warn, error, critical, off)");
}

TEST(Logging, FlagBeatsEnvironmentBeatsDefault) {
  ::unsetenv(kLogLevelEnv);
  EXPECT_EQ(resolveLogLevel("").value(), spdlog::level::info);
  ::setenv(kLogLevelEnv, "trace", 1);
  EXPECT_EQ(resolveLogLevel("").value(), spdlog::level::trace);
  EXPECT_EQ(resolveLogLevel("error").value(), spdlog::level::err);
  ::setenv(kLogLevelEnv, "chatty", 1);
  auto bad_env = resolveLogLevel("");
  ASSERT_FALSE(bad_env.ok());
  EXPECT_NE(bad_env.error().find("SEMFUSE_LOG_LEVEL: unknown log level 'chatty'"), std::string::npos);
  ::unsetenv(kLogLevelEnv);
}

TEST(Logging, SetupInstallsNamedDefaultLoggerAndCanRunTwice) {
  ::unsetenv(kLogLevelEnv);
  ASSERT_TRUE(setupLogging("semfuse-test", "debug").ok());
  EXPECT_EQ(spdlog::default_logger()->name(), "semfuse-test");
  EXPECT_EQ(spdlog::default_logger()->level(), spdlog::level::debug);
  const Status bad = setupLogging("semfuse-test", "nonsense");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("--log-level: unknown log level 'nonsense'"), std::string::npos);
  EXPECT_EQ(spdlog::default_logger()->level(), spdlog::level::info);  // still usable
}

}  // namespace
}  // namespace semfuse
