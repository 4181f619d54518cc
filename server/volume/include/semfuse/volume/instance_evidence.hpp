#pragma once
// Panoptic instance evidence: which object instance a voxel belongs to, from segmenters that give
// an instance map beside their labels. One 32-bit value per voxel in an Int32Grid whose leaves are
// a subset of the geometry's (allocated where instance maps were fused): the map-wide instance id
// in the low 24 bits, the evidence for it in the high 8 (observations that agreed, less those that
// named another instance; the id changes when it reaches zero, as Algorithm 1 does for labels).
// All-zero is no evidence. A segmenter's instance ids are its own and may change from frame to
// frame; integrateInstances() (instance_integration.hpp) matches them to the map's ids by overlap.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>

namespace semfuse::volume {

using InstanceGrid = openvdb::Int32Grid;
using PackedInstance = openvdb::Int32;

inline constexpr uint32_t kMaxInstanceId = (1u << 24) - 1;
inline constexpr uint32_t kMaxInstanceEvidence = 255;

inline PackedInstance packInstance(uint32_t id, uint32_t evidence) {
  return static_cast<PackedInstance>((evidence << 24) | (id & kMaxInstanceId));
}
inline uint32_t instanceIdOf(PackedInstance packed) { return static_cast<uint32_t>(packed) & kMaxInstanceId; }
inline uint32_t instanceEvidenceOf(PackedInstance packed) { return static_cast<uint32_t>(packed) >> 24; }

// One key per unordered pair of instance ids.
inline uint64_t instancePairKey(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t{a} << 32 | b) : (uint64_t{b} << 32 | a);
}
// Whether the pair of a and b is among sorted pair keys.
inline bool hasInstancePair(const std::vector<uint64_t>& sorted_keys, uint32_t a, uint32_t b) {
  return std::binary_search(sorted_keys.begin(), sorted_keys.end(), instancePairKey(a, b));
}

}  // namespace semfuse::volume
