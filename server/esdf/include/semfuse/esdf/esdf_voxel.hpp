#pragma once
// The packed ESDF voxel: 8 bytes in an openvdb::Int64Grid with the TSDF's leaves and transform.
//
//   bits  0-47  offset to the voxel's nearest site (dx, dy, dz: int16 each, voxels)
//   bits 48-55  the site's own distance to the surface, in 1/255 voxel (at most one voxel)
//   bit  56     inside (the site and the voxel are on the surface's negative side)
//   bit  57     has a site within the maximum distance (else: at least the maximum distance away)
//   bit  58     is a site itself (offset 0)
//   bit  63     an update's transient mark (isMarked): set and cleared within one step of it,
//               never seen by queries or files
//
// Active = observed (known); inactive voxels are unknown. The distance is not stored: it is
// |offset| + the site's distance (voxels), negative inside, which keeps the voxel exact however
// often its site's neighbourhood is updated and lets one 64-bit word hold the whole state
// (voxblox and nvblox store the same "parent" offset beside a float distance).
#include <cmath>
#include <cstdint>

#include <openvdb/openvdb.h>

namespace semfuse::esdf {

using PackedEsdf = openvdb::Int64;
using EsdfGrid = openvdb::Int64Grid;

struct EsdfVoxel {
  int16_t dx = 0, dy = 0, dz = 0;  // site = this voxel + (dx, dy, dz)
  uint8_t site_distance = 0;       // the site's distance to the surface, 1/255 voxel
  bool inside = false;
  bool has_site = false;
  bool is_site = false;

  // Distance in voxels to the surface through the site, >= 0 (undefined without a site).
  float magnitude() const {
    const float squared = float(dx) * dx + float(dy) * dy + float(dz) * dz;
    return std::sqrt(squared) + site_distance * (1.0f / 255.0f);
  }
  // Signed distance in voxels, clamped at +-max_voxels where no site is within the maximum.
  float signedDistance(float max_voxels) const {
    const float d = has_site ? std::min(magnitude(), max_voxels) : max_voxels;
    return inside ? -d : d;
  }
  openvdb::Coord site(const openvdb::Coord& ijk) const { return ijk.offsetBy(dx, dy, dz); }
};

namespace detail {
inline uint64_t u16(int16_t v) { return static_cast<uint64_t>(static_cast<uint16_t>(v)); }
inline int16_t s16(uint64_t bits) { return static_cast<int16_t>(static_cast<uint16_t>(bits & 0xFFFFu)); }
}  // namespace detail

inline constexpr uint64_t kInsideBit = uint64_t{1} << 56;
inline constexpr uint64_t kHasSiteBit = uint64_t{1} << 57;
inline constexpr uint64_t kIsSiteBit = uint64_t{1} << 58;

inline constexpr uint64_t kMarkBit = uint64_t{1} << 63;
inline bool isMarked(PackedEsdf packed) { return (static_cast<uint64_t>(packed) & kMarkBit) != 0; }
inline PackedEsdf withMark(PackedEsdf packed) {
  return static_cast<PackedEsdf>(static_cast<uint64_t>(packed) | kMarkBit);
}
inline PackedEsdf withoutMark(PackedEsdf packed) {
  return static_cast<PackedEsdf>(static_cast<uint64_t>(packed) & ~kMarkBit);
}

inline PackedEsdf packEsdf(const EsdfVoxel& v) {
  const uint64_t bits = detail::u16(v.dx) | (detail::u16(v.dy) << 16) | (detail::u16(v.dz) << 32) |
                        (uint64_t{v.site_distance} << 48) | (v.inside ? kInsideBit : 0) |
                        (v.has_site ? kHasSiteBit : 0) | (v.is_site ? kIsSiteBit : 0);
  return static_cast<PackedEsdf>(bits);
}

inline EsdfVoxel unpackEsdf(PackedEsdf packed) {
  const auto bits = static_cast<uint64_t>(packed);
  EsdfVoxel v;
  v.dx = detail::s16(bits);
  v.dy = detail::s16(bits >> 16);
  v.dz = detail::s16(bits >> 32);
  v.site_distance = static_cast<uint8_t>(bits >> 48);
  v.inside = (bits & kInsideBit) != 0;
  v.has_site = (bits & kHasSiteBit) != 0;
  v.is_site = (bits & kIsSiteBit) != 0;
  return v;
}

}  // namespace semfuse::esdf
