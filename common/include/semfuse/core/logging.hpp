#pragma once
// One logging setup for every semfuse program: spdlog's default logger on stderr with a short
// pattern ("12:34:56.789 I semfuse-server: message"), level chosen by --log-level, else the
// SEMFUSE_LOG_LEVEL environment variable, else info.
#include <string>

#include <spdlog/common.h>

#include "semfuse/core/result.hpp"

namespace semfuse {

inline constexpr const char* kLogLevelEnv = "SEMFUSE_LOG_LEVEL";

// "trace", "debug", "info", "warn"/"warning", "error"/"err", "critical", "off" (any case).
Result<spdlog::level::level_enum> parseLogLevel(const std::string& text);

// The level a program should use: `flag_value` when non-empty, else $SEMFUSE_LOG_LEVEL when set,
// else info. An invalid value is an error naming where it came from.
Result<spdlog::level::level_enum> resolveLogLevel(const std::string& flag_value);

// Installs the default logger for `program` (its name appears in every line) at the resolved level.
// On an invalid level it still installs the logger at info and returns the error to report.
Status setupLogging(const std::string& program, const std::string& level_flag = "");

// The allowed level names, for --help texts.
const char* logLevelNames();

}  // namespace semfuse
