#pragma once
// Small helpers shared by the fuzz targets.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

namespace semfuse::fuzz {

// A fuzz invariant: unlike assert() it also holds in Release builds, and aborts so that both
// libFuzzer and the ctest replay report the input.
#define SEMFUSE_FUZZ_CHECK(condition)                                                          \
  do {                                                                                         \
    if (!(condition)) {                                                                        \
      std::fprintf(stderr, "fuzz check failed: %s (%s:%d)\n", #condition, __FILE__, __LINE__); \
      std::abort();                                                                            \
    }                                                                                          \
  } while (0)

// A private folder for targets whose code under test reads files (map files, dataset lists),
// made once per process and removed at exit.
inline const std::filesystem::path& scratchFolder() {
  // Never destroyed, so the exit handler below can still read it.
  static const std::filesystem::path* const folder = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "semfuse-fuzz-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      std::perror("mkdtemp");
      std::abort();
    }
    return new std::filesystem::path(pattern);
  }();
  static const bool cleanup_registered = [] {
    return std::atexit([] {
             std::error_code ignored;
             std::filesystem::remove_all(*folder, ignored);
           }) == 0;
  }();
  (void)cleanup_registered;
  return *folder;
}

// Writes `bytes` to `name` in the scratch folder (replacing it) and returns its path.
inline std::filesystem::path writeScratchFile(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratchFolder() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

// Splits an input into parts at a separator line (used where one input stands for several files).
inline std::string_view nextPart(std::string_view& rest, std::string_view separator) {
  const std::size_t at = rest.find(separator);
  if (at == std::string_view::npos) {
    const std::string_view part = rest;
    rest = {};
    return part;
  }
  const std::string_view part = rest.substr(0, at);
  rest.remove_prefix(at + separator.size());
  return part;
}

}  // namespace semfuse::fuzz
