// readVoxelColumnsAvx2: the 8 voxels z = 0..7 of a column in one register. Only these functions
// carry target("avx2,f16c"); everything else this file calls stays baseline x86-64, so that no
// AVX2 code can be picked by the linker for a CPU without it (as in the volume's leaf_update_avx2).
#include "voxel_columns.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SEMFUSE_HAVE_AVX2_COLUMNS 1
#include <cpuid.h>
#include <immintrin.h>
#else
#define SEMFUSE_HAVE_AVX2_COLUMNS 0
#endif

namespace semfuse::render::detail {

#if SEMFUSE_HAVE_AVX2_COLUMNS
#define SEMFUSE_AVX2 __attribute__((target("avx2,f16c")))
namespace {

// Voxels z = 0..7 at `voxels`: their TSDF as floats to brick_column[0..7]; bit z of `seen` /
// `below` where voxel z is observed / has TSDF bits <= 0 (nonPositiveBits).
SEMFUSE_AVX2 inline void readColumn8(const volume::PackedVoxel* voxels, float* brick_column, unsigned& seen,
                                     unsigned& below) {
  // The low 32 bits of each 64-bit voxel (TSDF half | weight half << 16), lane z = voxel z: even
  // dwords per 128-bit half give voxels (0 1 4 5 | 2 3 6 7); swapping the middle pairs restores 0-7.
  const __m256 a = _mm256_castsi256_ps(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(voxels)));
  const __m256 b = _mm256_castsi256_ps(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(voxels + 4)));
  const __m256i low = _mm256_permute4x64_epi64(_mm256_castps_si256(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))),
                                               _MM_SHUFFLE(3, 1, 2, 0));
  const __m256i unobserved = _mm256_cmpeq_epi32(_mm256_and_si256(low, _mm256_set1_epi32(static_cast<int>(0xFFFF0000u))),
                                                _mm256_setzero_si256());
  seen = ~static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(unobserved))) & 0xFFu;
  // The TSDF half in the upper 16 bits of each lane: <= 0 as a signed integer is nonPositiveBits.
  const __m256i non_positive = _mm256_cmpgt_epi32(_mm256_set1_epi32(1), _mm256_slli_epi32(low, 16));
  below = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(non_positive)));
  // The 8 halves side by side (packus keeps them: each is <= 0xFFFF), then converted exactly.
  const __m256i halves = _mm256_and_si256(low, _mm256_set1_epi32(0xFFFF));
  const __m256i packed = _mm256_permute4x64_epi64(_mm256_packus_epi32(halves, halves), _MM_SHUFFLE(3, 1, 2, 0));
  _mm256_storeu_ps(brick_column, _mm256_cvtph_ps(_mm256_castsi256_si128(packed)));
}

}  // namespace

SEMFUSE_AVX2 void readVoxelColumnsAvx2(const CrossingCells::LeafCells& leaf, float* brick, VoxelColumns& columns) {
  constexpr int kSpan = VoxelColumns::kSpan;
  for (int x = 0; x < kSpan; ++x)
    for (int y = 0; y < kSpan; ++y) {
      const ColumnSource source = columnSource(leaf, x, y);
      float* brick_column = brick + CrossingCells::kBrickStride * x + CrossingCells::kBrickDim * y;
      unsigned seen = 0, below = 0;
      if (source.low) {
        readColumn8(source.low, brick_column, seen, below);
      } else {
        _mm256_storeu_ps(brick_column, _mm256_setzero_ps());
      }
      finishColumn(source, brick_column, seen, below, x, y, columns);
    }
}

bool voxelColumnsAvx2Supported() {
  static const bool supported = [] {
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    if (__get_cpuid(1, &eax, &ebx, &ecx, &edx) == 0) return false;
    return (ecx & bit_F16C) != 0 && __builtin_cpu_supports("avx2");
  }();
  return supported;
}

#undef SEMFUSE_AVX2  // a unity build compiles other files after this one
#else

void readVoxelColumnsAvx2(const CrossingCells::LeafCells& leaf, float* brick, VoxelColumns& columns) {
  readVoxelColumns(leaf, brick, columns);  // never chosen: voxelColumnsAvx2Supported() is false
}
bool voxelColumnsAvx2Supported() { return false; }

#endif

}  // namespace semfuse::render::detail
