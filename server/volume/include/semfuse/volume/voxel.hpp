#pragma once
// The packed per-voxel layout: geometry and label evidence in 8 bytes, as in the paper.
//
//   bits  0-15  tsdf    half float, metres, within [-truncation, +truncation]
//   bits 16-31  weight  half float, >= 0; 0 means "never observed"
//   bits 32-47  label   uint16, 0 = unlabeled
//   bits 48-63  score   half float, label evidence (Algorithm 1); may be negative transiently
//
// All-zero bits are the unobserved voxel, which is also the grid's background value, so a freshly
// allocated leaf needs no initialisation. The 64 bits live in an openvdb::Int64Grid: a registered,
// serialisable grid type, 8 bytes per voxel plus tree overhead. Colour lives in a separate
// Int32Grid with the same topology (0x00RRGGBB), so maps without colour pay nothing for it.
#include <cstdint>
#include <cstring>

#include <openvdb/math/Half.h>
#include <openvdb/openvdb.h>

#include "semfuse/core/legend.hpp"

namespace semfuse::volume {

using PackedVoxel = openvdb::Int64;
using GeometryGrid = openvdb::Int64Grid;  // PackedVoxel per voxel; active = observed
using ColorGrid = openvdb::Int32Grid;     // PackedColor per voxel, same topology as geometry
using PackedColor = openvdb::Int32;
using FreeSpaceGrid = openvdb::MaskGrid;  // on = observed free space (free_space.hpp)

inline constexpr PackedVoxel kUnobservedVoxel = 0;

// Unpacked view of one voxel.
struct VoxelValue {
  float tsdf = 0.0f;    // metres (not normalised by the truncation)
  float weight = 0.0f;  // 0 = unobserved
  LabelId label = kUnlabeled;
  float score = 0.0f;

  bool observed() const { return weight > 0.0f; }
};

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb8& a, const Rgb8& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }
};

namespace detail {
// IEEE binary16 <-> binary32 without tables or calls. openvdb::math::half converts half -> float
// through a 256 KiB table and float -> half through an out-of-line function; in the integration
// loop (several conversions per voxel, a million voxels per frame) both showed in the profile.
// These are plain integer/float arithmetic that inlines (and vectorises), and give the same bits
// as openvdb::math::half for every input: round to nearest even, subnormals, +-inf, NaN stays NaN
// (tests/volume/voxel_test.cpp checks all 65536 halves and a sweep of floats).
inline uint32_t floatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
inline float bitsFloat(uint32_t u) {
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

inline uint16_t halfBits(float value) {
  const uint32_t bits = floatBits(value);
  const uint32_t sign = (bits >> 16) & 0x8000u;
  const uint32_t magnitude = bits & 0x7FFFFFFFu;
  uint32_t half;
  if (magnitude >= 0x47800000u) {                        // >= 65536 (2^16), inf or NaN: all exponent bits set
    half = magnitude > 0x7F800000u ? 0x7E00u : 0x7C00u;  // NaN -> quiet NaN, else inf
  } else if (magnitude < 0x38800000u) {                  // < 2^-14: the half is subnormal (or zero)
    // Adding 0.5 aligns the float's mantissa so that its low bits are the half's subnormal
    // mantissa (units of 2^-24); the FPU's own rounding of that sum is round-to-nearest-even.
    half = floatBits(bitsFloat(magnitude) + 0.5f) - 0x3F000000u;
  } else {
    // Rebias the exponent (127 -> 15) and drop 13 mantissa bits, rounding to nearest even: add
    // just under half an ulp, plus one when the kept part is odd. A carry into the exponent is
    // the correct rounding up (to inf above 65519.99...).
    const uint32_t odd = (magnitude >> 13) & 1u;
    half = (magnitude - 0x38000000u + 0x0FFFu + odd) >> 13;
  }
  return static_cast<uint16_t>(half | sign);
}

inline float halfValue(uint64_t bits) {
  const auto h = static_cast<uint32_t>(bits & 0xFFFFu);
  const uint32_t sign = (h & 0x8000u) << 16;
  const uint32_t shifted = (h & 0x7FFFu) << 13;  // exponent and mantissa in float position
  const uint32_t exponent = h & 0x7C00u;
  float magnitude;
  if (exponent == 0x7C00u) {
    magnitude = bitsFloat(shifted | 0x7F800000u);  // inf / NaN (payload kept)
  } else if (exponent == 0) {
    // Subnormal m * 2^-24: read the bits as 2^-14 * (1 + m / 1024) and subtract 2^-14, exactly.
    magnitude = bitsFloat(shifted + 0x38800000u) - bitsFloat(0x38800000u);
  } else {
    magnitude = bitsFloat(shifted + 0x38000000u);  // rebias the exponent 15 -> 127
  }
  return bitsFloat(floatBits(magnitude) | sign);
}
// The same value as halfValue() without branches, for loops that convert many halves at once
// (the compiler vectorises it): the half's exponent and mantissa moved into float position read
// as a float 2^112 times too small, for normal and subnormal halves alike, and multiplying by
// 2^112 is exact; infinities and NaNs are patched in with a mask.
inline float halfValueBranchless(uint64_t bits) {
  const auto h = static_cast<uint32_t>(bits & 0xFFFFu);
  const uint32_t shifted = (h & 0x7FFFu) << 13;
  const float scaled = bitsFloat(shifted) * 0x1p112f;
  const uint32_t special = 0u - static_cast<uint32_t>((h & 0x7C00u) == 0x7C00u);  // all ones for inf / NaN
  const uint32_t magnitude = (floatBits(scaled) & ~special) | ((shifted | 0x7F800000u) & special);
  return bitsFloat(magnitude | ((h & 0x8000u) << 16));
}
inline uint64_t asBits(PackedVoxel v) { return static_cast<uint64_t>(v); }
}  // namespace detail

inline PackedVoxel packVoxel(float tsdf, float weight, LabelId label, float score) {
  const uint64_t bits = uint64_t{detail::halfBits(tsdf)} | (uint64_t{detail::halfBits(weight)} << 16) |
                        (uint64_t{label} << 32) | (uint64_t{detail::halfBits(score)} << 48);
  return static_cast<PackedVoxel>(bits);
}
inline PackedVoxel packVoxel(const VoxelValue& v) { return packVoxel(v.tsdf, v.weight, v.label, v.score); }

inline float unpackTsdf(PackedVoxel v) { return detail::halfValue(detail::asBits(v)); }
inline float unpackWeight(PackedVoxel v) { return detail::halfValue(detail::asBits(v) >> 16); }
inline LabelId unpackLabel(PackedVoxel v) { return static_cast<LabelId>(detail::asBits(v) >> 32); }
inline float unpackScore(PackedVoxel v) { return detail::halfValue(detail::asBits(v) >> 48); }
// Weight bits are non-zero exactly when the weight is > 0 (weights are never negative zero).
inline bool isObserved(PackedVoxel v) { return (detail::asBits(v) & 0xFFFF0000u) != 0; }

inline VoxelValue unpackVoxel(PackedVoxel v) {
  return {unpackTsdf(v), unpackWeight(v), unpackLabel(v), unpackScore(v)};
}

inline PackedColor packColor(Rgb8 c) {
  return static_cast<PackedColor>((uint32_t{c.r} << 16) | (uint32_t{c.g} << 8) | uint32_t{c.b});
}
inline Rgb8 unpackColor(PackedColor c) {
  const auto u = static_cast<uint32_t>(c);
  return {static_cast<uint8_t>(u >> 16), static_cast<uint8_t>(u >> 8), static_cast<uint8_t>(u)};
}
// Rec. 601 luma (0..1) of a packed colour: the grey level a camera's intensity image has.
inline float unpackLuma(PackedColor packed) {
  const Rgb8 c = unpackColor(packed);
  return (0.299f * c.r + 0.587f * c.g + 0.114f * c.b) * (1.0f / 255.0f);
}

}  // namespace semfuse::volume
