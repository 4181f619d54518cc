#include "semfuse/core/logging.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace semfuse {

const char* logLevelNames() { return "trace, debug, info, warn, error, critical, off"; }

Result<spdlog::level::level_enum> parseLogLevel(const std::string& text) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  using spdlog::level::level_enum;
  if (lower == "trace") return level_enum::trace;
  if (lower == "debug") return level_enum::debug;
  if (lower == "info") return level_enum::info;
  if (lower == "warn" || lower == "warning") return level_enum::warn;
  if (lower == "error" || lower == "err") return level_enum::err;
  if (lower == "critical") return level_enum::critical;
  if (lower == "off") return level_enum::off;
  return makeError("unknown log level '" + text + "' (use one of " + logLevelNames() + ")");
}

Result<spdlog::level::level_enum> resolveLogLevel(const std::string& flag_value) {
  if (!flag_value.empty()) {
    auto level = parseLogLevel(flag_value);
    if (!level) return makeError("--log-level: " + level.error());
    return level;
  }
  if (const char* env = std::getenv(kLogLevelEnv); env && *env) {
    auto level = parseLogLevel(env);
    if (!level) return makeError(std::string(kLogLevelEnv) + ": " + level.error());
    return level;
  }
  return spdlog::level::info;
}

Status setupLogging(const std::string& program, const std::string& level_flag) {
  // Diagnostics go to stderr so that programs can write data (JSON, tables) to stdout.
  // Built directly rather than with spdlog::stderr_color_mt, which throws when a logger of that
  // name exists: setupLogging may run more than once in a process (tests, restarts).
  auto logger = std::make_shared<spdlog::logger>(program.empty() ? "semfuse" : program,
                                                 std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  // %L: one-letter level; %n: logger (program) name.
  logger->set_pattern("%H:%M:%S.%e %^%L%$ %n: %v");
  auto level = resolveLogLevel(level_flag);
  logger->set_level(level ? level.value() : spdlog::level::info);
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(logger);
  if (!level) return makeError(level.error());
  return Status::Ok();
}

}  // namespace semfuse
