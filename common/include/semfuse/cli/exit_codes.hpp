#pragma once
// Exit codes shared by the semfuse command-line programs, so that scripts can tell a typo from a
// server that said no from a server that never answered.
namespace semfuse::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;      // anything else (bad input file, DDS failure)
inline constexpr int kExitUsage = 2;        // bad command line: help was printed
inline constexpr int kExitServerError = 3;  // the server replied with an error
inline constexpr int kExitTimeout = 4;      // no server, or no reply in time

}  // namespace semfuse::cli
