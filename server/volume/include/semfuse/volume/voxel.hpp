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

#include <openvdb/math/Half.h>
#include <openvdb/openvdb.h>

#include "semfuse/core/legend.hpp"

namespace semfuse::volume {

using PackedVoxel = openvdb::Int64;
using GeometryGrid = openvdb::Int64Grid;  // PackedVoxel per voxel; active = observed
using ColorGrid = openvdb::Int32Grid;     // PackedColor per voxel, same topology as geometry
using PackedColor = openvdb::Int32;

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
inline uint16_t halfBits(float value) { return openvdb::math::half(value).bits(); }
inline float halfValue(uint64_t bits) {
  openvdb::math::half h;
  h.setBits(static_cast<unsigned short>(bits & 0xFFFFu));
  return static_cast<float>(h);
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

}  // namespace semfuse::volume
