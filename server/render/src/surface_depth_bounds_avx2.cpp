// rasterizeBand's loops over pixels, 8 lanes at a time. Only these functions carry
// target("avx2"); everything else this file calls stays baseline x86-64, so that no AVX2 code can
// be picked by the linker for a CPU without it (as in voxel_columns_avx2.cpp). No "fma" in the
// target: the compiler must not fuse a multiply and an add that the portable loops round apart,
// or the bounds, and with them the images, would differ between the kernels.
#include "surface_depth_bounds.hpp"

#include <algorithm>
#include <cstddef>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SEMFUSE_HAVE_AVX2_BOUNDS 1
#else
#define SEMFUSE_HAVE_AVX2_BOUNDS 0
#endif

namespace semfuse::render::detail {

#if SEMFUSE_HAVE_AVX2_BOUNDS
#define SEMFUSE_AVX2 __attribute__((target("avx2")))
namespace {

using namespace bounds_constants;

// x with the sign bit of `sign` (std::copysign).
SEMFUSE_AVX2 inline __m256 copySign(__m256 x, __m256 sign) {
  const __m256 sign_bit = _mm256_set1_ps(-0.0f);
  return _mm256_or_ps(_mm256_andnot_ps(sign_bit, x), _mm256_and_ps(sign_bit, sign));
}

// std::min(a, b) and std::max(a, b) lane by lane, operand order included: min returns a unless
// b < a, max returns a unless a < b (what the portable loops compute, down to the sign of a zero).
SEMFUSE_AVX2 inline __m256 minLikeStd(__m256 a, __m256 b) { return _mm256_min_ps(b, a); }
SEMFUSE_AVX2 inline __m256 maxLikeStd(__m256 a, __m256 b) { return _mm256_max_ps(b, a); }

}  // namespace

SEMFUSE_AVX2 void fillInverseDirectionsAvx2(const SurfaceDepthBounds::BandView& band, const double ray_du[3],
                                            const double ray_dv[3], const double ray_at_origin[3]) {
  const std::size_t pixels = band.pixels();
  const __m256 huge = _mm256_set1_ps(kHugeInverse), minus_huge = _mm256_set1_ps(-kHugeInverse);
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (int a = 0; a < 3; ++a)
    for (int v = band.v_begin; v < band.v_begin + band.rows; ++v) {
      float* row = band.inverse_direction + a * pixels + static_cast<std::size_t>(v - band.v_begin) * band.width;
      const __m256 du = _mm256_set1_ps(static_cast<float>(ray_du[a]));
      const __m256 at_u0 = _mm256_set1_ps(static_cast<float>(ray_dv[a] * v + ray_at_origin[a]));
      // Up to 7 lanes past the row's end: they land in the next row (written again there) or in
      // the padding.
      for (int u = 0; u < band.width; u += 8) {
        const __m256 column = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(u), lane));
        const __m256 inverse = _mm256_div_ps(one, _mm256_add_ps(_mm256_mul_ps(du, column), at_u0));
        // std::clamp(x, lo, hi): lo if x < lo, else hi if hi < x, else x.
        const __m256 clamped =
            _mm256_blendv_ps(_mm256_blendv_ps(inverse, huge, _mm256_cmp_ps(huge, inverse, _CMP_LT_OQ)), minus_huge,
                             _mm256_cmp_ps(inverse, minus_huge, _CMP_LT_OQ));
        _mm256_storeu_ps(row + u, clamped);
      }
    }
}

SEMFUSE_AVX2 void clipRectsAvx2(const SurfaceDepthBounds::BandView& band, const SurfaceDepthBounds::Rect* first,
                                const SurfaceDepthBounds::Rect* last) {
  const std::size_t pixels = band.pixels();
  const __m256 near_margin = _mm256_set1_ps(band.near_margin), far_margin = _mm256_set1_ps(band.far_margin);
  const __m256 tiny = _mm256_set1_ps(kTinySlope), beyond_any = _mm256_set1_ps(kBeyondAnyDepth);
  const __m256 sign_bit = _mm256_set1_ps(-0.0f);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (const SurfaceDepthBounds::Rect* rect = first; rect != last; ++rect) {
    const SurfaceDepthBounds::Rect& f = *rect;
    const __m256 lx = _mm256_set1_ps(f.low[0]), hx = _mm256_set1_ps(f.high[0]);
    const __m256 ly = _mm256_set1_ps(f.low[1]), hy = _mm256_set1_ps(f.high[1]);
    const __m256 lz = _mm256_set1_ps(f.low[2]), hz = _mm256_set1_ps(f.high[2]);
    const __m256 plane_du = _mm256_set1_ps(f.plane_du), plane_c = _mm256_set1_ps(f.plane_c);
    const __m256i last_column = _mm256_set1_epi32(f.u1);
    const int v0 = std::max(f.v0, band.v_begin), v1 = std::min(f.v1, band.v_begin + band.rows - 1);
    for (int v = v0; v <= v1; ++v) {
      const std::size_t row_start = static_cast<std::size_t>(v - band.v_begin) * band.width;
      float* near_row = band.near + row_start;
      float* far_row = band.far + row_start;
      const float* inv_x = band.inverse_direction + row_start;
      const float* inv_y = inv_x + pixels;
      const float* inv_z = inv_y + pixels;
      const __m256 plane_row = _mm256_set1_ps(f.plane_dv * static_cast<float>(v) + f.plane_at_origin);
      for (int u = f.u0; u <= f.u1; u += 8) {
        // Lanes past u1 read pixels of no concern (later in the row, the next row, the padding)
        // and store back what they read.
        const __m256i columns = _mm256_add_epi32(_mm256_set1_epi32(u), lane);
        const __m256 past_u1 = _mm256_castsi256_ps(_mm256_cmpgt_epi32(columns, last_column));
        const __m256 ix = _mm256_loadu_ps(inv_x + u), iy = _mm256_loadu_ps(inv_y + u), iz = _mm256_loadu_ps(inv_z + u);
        const __m256 x0 = _mm256_mul_ps(lx, ix), x1 = _mm256_mul_ps(hx, ix);
        const __m256 y0 = _mm256_mul_ps(ly, iy), y1 = _mm256_mul_ps(hy, iy);
        const __m256 z0 = _mm256_mul_ps(lz, iz), z1 = _mm256_mul_ps(hz, iz);
        const __m256 a = _mm256_add_ps(_mm256_mul_ps(plane_du, _mm256_cvtepi32_ps(columns)), plane_row);
        const __m256 a_safe = copySign(maxLikeStd(_mm256_andnot_ps(sign_bit, a), tiny), a);
        const __m256 t_plane = _mm256_div_ps(plane_c, a_safe);
        const __m256 beyond = copySign(beyond_any, _mm256_xor_ps(a_safe, sign_bit));
        const __m256 plane_enter = minLikeStd(t_plane, beyond);
        const __m256 plane_leave = maxLikeStd(t_plane, beyond);
        const __m256 enter =
            maxLikeStd(maxLikeStd(maxLikeStd(minLikeStd(x0, x1), minLikeStd(y0, y1)), minLikeStd(z0, z1)), plane_enter);
        const __m256 leave =
            minLikeStd(minLikeStd(minLikeStd(maxLikeStd(x0, x1), maxLikeStd(y0, y1)), maxLikeStd(z0, z1)), plane_leave);
        // (enter > leave) x kBeyondAnyDepth: exactly kBeyondAnyDepth or +0.
        const __m256 missed = _mm256_and_ps(_mm256_cmp_ps(enter, leave, _CMP_GT_OQ), beyond_any);
        const __m256 near_old = _mm256_loadu_ps(near_row + u), far_old = _mm256_loadu_ps(far_row + u);
        const __m256 near_new = minLikeStd(near_old, _mm256_add_ps(_mm256_sub_ps(enter, near_margin), missed));
        const __m256 far_new = maxLikeStd(far_old, _mm256_sub_ps(_mm256_add_ps(leave, far_margin), missed));
        _mm256_storeu_ps(near_row + u, _mm256_blendv_ps(near_new, near_old, past_u1));
        _mm256_storeu_ps(far_row + u, _mm256_blendv_ps(far_new, far_old, past_u1));
      }
    }
  }
}

#undef SEMFUSE_AVX2  // a unity build compiles other files after this one
#else                // not x86-64: never chosen (raycastKernel() is never kAvx2 there)

void fillInverseDirectionsAvx2(const SurfaceDepthBounds::BandView& band, const double ray_du[3], const double ray_dv[3],
                               const double ray_at_origin[3]) {
  fillInverseDirections(band, ray_du, ray_dv, ray_at_origin);
}
void clipRectsAvx2(const SurfaceDepthBounds::BandView& band, const SurfaceDepthBounds::Rect* first,
                   const SurfaceDepthBounds::Rect* last) {
  clipRects(band, first, last);
}

#endif

}  // namespace semfuse::render::detail
