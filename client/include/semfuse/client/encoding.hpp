#pragma once
// How a CameraPublisher puts images on the wire (see the Frame_ comment in idl/semfuse/msg.idl).
// Raw costs no CPU and much bandwidth; PNG and RVL are lossless and several times smaller for
// depth, RVL much cheaper to decode on the server than PNG (semfuse-bench depth-codecs); JPEG is
// lossy and ~10x smaller for colour, which the server only uses for display and meshing.
#include <optional>
#include <string>

namespace semfuse::client {

enum class DepthEncoding {
  kRaw16,     // "16UC1": millimetres, 1 mm resolution, 65.5 m range
  kRawFloat,  // "32FC1": float metres, exact
  kPng16,     // "png16": the 16-bit millimetre image, PNG-compressed
  kRvl,       // "rvl": the 16-bit millimetre image, RVL-compressed (semfuse/wire/rvl_codec.hpp)
};

enum class ColorEncoding {
  kNone,  // frame travels without colour
  kRaw,   // "rgb8"
  kJpeg,  // "jpeg"
  kPng,   // "png"
};

// Parse the CLI spellings: depth raw|float|png|rvl, colour none|raw|jpeg|png.
std::optional<DepthEncoding> parseDepthEncoding(const std::string& text);
std::optional<ColorEncoding> parseColorEncoding(const std::string& text);

}  // namespace semfuse::client
