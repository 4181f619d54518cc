#pragma once
// A share as the reports print it: one decimal and a percent sign ("12.5%").
#include <cstdio>
#include <string>

namespace semfuse::eval {

inline std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
  return text;
}

}  // namespace semfuse::eval
