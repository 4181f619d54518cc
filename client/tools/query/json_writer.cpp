#include "json_writer.hpp"

#include <cmath>
#include <cstdio>

namespace semfuse::tools {

std::string JsonObject::toJson(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no NaN or infinity
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::string jsonArray(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

}  // namespace semfuse::tools
