#pragma once
// Internal: conversion between the packed in-memory grid and the per-layer grids of a map file
// (tsdf level set, weight, score, label), and a checksum of the packed voxels.
#include <cstdint>

#include <openvdb/openvdb.h>

#include "semfuse/core/result.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume::detail {

struct MapLayers {
  openvdb::FloatGrid::Ptr tsdf;    // level set: background +truncation, active = observed
  openvdb::FloatGrid::Ptr weight;  // these three share the tsdf's topology
  openvdb::FloatGrid::Ptr score;
  openvdb::Int32Grid::Ptr label;
};

// Splits the packed grid into layers with the same topology (allocated leaves included).
MapLayers splitLayers(const LabeledVolume& volume);

// Rebuilds the packed tree from layers read from a file; fails on mismatched topologies or values
// the packed layout cannot hold (labels outside uint16, negative or non-finite weights).
Result<GeometryGrid::TreeType::Ptr> mergeLayers(const MapLayers& layers);

// FNV-1a over every leaf's origin, active mask and packed values (and colours when given), in
// tree order: the same map gives the same number, a flipped bit a different one.
uint64_t voxelChecksum(const GeometryGrid::TreeType& geometry, const ColorGrid::TreeType* color);

}  // namespace semfuse::volume::detail
