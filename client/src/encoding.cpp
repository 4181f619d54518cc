#include "semfuse/client/encoding.hpp"

namespace semfuse::client {

std::optional<DepthEncoding> parseDepthEncoding(const std::string& text) {
  if (text == "raw") return DepthEncoding::kRaw16;
  if (text == "float") return DepthEncoding::kRawFloat;
  if (text == "png") return DepthEncoding::kPng16;
  if (text == "rvl") return DepthEncoding::kRvl;
  return std::nullopt;
}

std::optional<ColorEncoding> parseColorEncoding(const std::string& text) {
  if (text == "none") return ColorEncoding::kNone;
  if (text == "raw") return ColorEncoding::kRaw;
  if (text == "jpeg") return ColorEncoding::kJpeg;
  if (text == "png") return ColorEncoding::kPng;
  return std::nullopt;
}

}  // namespace semfuse::client
