#pragma once
// Counter-based randomness: a value depends only on its inputs (seed, frame, pixel, ...), never on
// call order, so rendering in parallel and re-rendering one frame give identical results on every
// platform (std::normal_distribution is not specified bit-exactly across standard libraries).
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

namespace semfuse::synthetic {

// SplitMix64 finaliser: a bijective, well-mixing 64-bit hash.
inline uint64_t mixBits(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline uint64_t hashCombine(uint64_t a, uint64_t b) { return mixBits(a ^ mixBits(b)); }

// Uniform in [0, 1) from a hash.
inline double unitFromHash(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// Standard normal from two independent hashes (Box-Muller).
inline double gaussianFromHashes(uint64_t h1, uint64_t h2) {
  const double u1 = 1.0 - unitFromHash(h1);  // (0, 1]: log stays finite
  const double u2 = unitFromHash(h2);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

// Smooth 3D value noise in [-1, 1]: hashed lattice values, trilinear with smoothstep weights.
inline double valueNoise(const Eigen::Vector3d& p, uint64_t seed) {
  const Eigen::Vector3d cell = p.array().floor();
  const Eigen::Vector3d f = p - cell;
  const Eigen::Vector3d w = f.array() * f.array() * (3.0 - 2.0 * f.array());
  // Lattice hash = hashCombine(hashCombine(hashCombine(seed, x), y), z): the 8 corners share
  // their x and xy prefixes, and each coordinate's own mix is needed once, so 20 mixes replace 48.
  // Same values, same summation order: bit-identical to hashing each corner from scratch.
  auto coordinateMix = [](double c, int offset) {
    return mixBits(static_cast<uint64_t>(static_cast<int64_t>(c) + offset));
  };
  const uint64_t mx[2] = {coordinateMix(cell.x(), 0), coordinateMix(cell.x(), 1)};
  const uint64_t my[2] = {coordinateMix(cell.y(), 0), coordinateMix(cell.y(), 1)};
  const uint64_t mz[2] = {coordinateMix(cell.z(), 0), coordinateMix(cell.z(), 1)};
  uint64_t hx[2], hxy[4];
  for (int dx = 0; dx < 2; ++dx) hx[dx] = mixBits(seed ^ mx[dx]);
  for (int i = 0; i < 4; ++i) hxy[i] = mixBits(hx[i & 1] ^ my[i >> 1]);
  double result = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    const double weight = (dx ? w.x() : 1 - w.x()) * (dy ? w.y() : 1 - w.y()) * (dz ? w.z() : 1 - w.z());
    result += weight * (2.0 * unitFromHash(mixBits(hxy[corner & 3] ^ mz[dz])) - 1.0);
  }
  return result;
}

}  // namespace semfuse::synthetic
