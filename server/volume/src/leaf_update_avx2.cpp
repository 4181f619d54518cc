// The AVX2 + F16C leaf update: one z-column of 8 voxels per 256-bit register. Projection, depth
// gather, band tests, the TSDF/weight running average, half conversions (vcvtph2ps/vcvtps2ph),
// the colour blend and the evidence rule (Algorithm 1, as masks and blends) run 8 voxels at a
// time; so does the top-5 rules' common case (a voxel without runner-up seeing its leader again),
// and their other updates, with the sidecar, stay per voxel on the lanes that need them.
//
// Only these functions carry target("avx2,f16c"): the rest of the library, and every inline
// library function this file instantiates out of line, stays baseline x86-64, so nothing compiled
// for AVX2 can be picked by the linker for a CPU without it. "fma" is deliberately not enabled:
// a contracted a * b + c rounds once, the scalar kernel twice, and the results must be identical.
#include "leaf_update.hpp"

#include <climits>
#include <limits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SEMFUSE_HAVE_AVX2_KERNEL 1
#include <cpuid.h>
#include <immintrin.h>
#else
#define SEMFUSE_HAVE_AVX2_KERNEL 0
#endif

namespace semfuse::volume::detail {

#if SEMFUSE_HAVE_AVX2_KERNEL
#define SEMFUSE_AVX2 __attribute__((target("avx2,f16c")))
namespace {

// The 8 packed voxels of a column as two registers of 32-bit lanes, lane z = voxel z:
// low = tsdf | weight << 16, high = label | score << 16.
struct ColumnVoxels {
  __m256i low, high;
};

SEMFUSE_AVX2 inline ColumnVoxels loadColumn(const PackedVoxel* voxels) {
  // a = dwords (l0 h0 l1 h1 | l2 h2 l3 h3), b = the same for voxels 4-7. Picking even/odd dwords
  // per 128-bit half gives (0 1 4 5 | 2 3 6 7); swapping the middle 64-bit pairs restores 0-7.
  const __m256 a = _mm256_castsi256_ps(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(voxels)));
  const __m256 b = _mm256_castsi256_ps(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(voxels + 4)));
  const __m256i low = _mm256_castps_si256(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)));
  const __m256i high = _mm256_castps_si256(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1)));
  return {_mm256_permute4x64_epi64(low, _MM_SHUFFLE(3, 1, 2, 0)),
          _mm256_permute4x64_epi64(high, _MM_SHUFFLE(3, 1, 2, 0))};
}

SEMFUSE_AVX2 inline void storeColumn(PackedVoxel* voxels, const ColumnVoxels& c) {
  const __m256i v0145 = _mm256_unpacklo_epi32(c.low, c.high);  // voxels 0 1 | 4 5
  const __m256i v2367 = _mm256_unpackhi_epi32(c.low, c.high);  // voxels 2 3 | 6 7
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(voxels), _mm256_permute2x128_si256(v0145, v2367, 0x20));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(voxels + 4), _mm256_permute2x128_si256(v0145, v2367, 0x31));
}

// Half floats in the low 16 bits of each 32-bit lane -> 8 floats.
SEMFUSE_AVX2 inline __m256 halvesToFloats(__m256i halves) {
  const __m128i packed = _mm_packus_epi32(_mm256_castsi256_si128(halves), _mm256_extracti128_si256(halves, 1));
  return _mm256_cvtph_ps(packed);
}

// 8 floats -> half floats (round to nearest even, as halfBits) in the low 16 bits of 32-bit lanes.
SEMFUSE_AVX2 inline __m256i floatsToHalves(__m256 values) {
  return _mm256_cvtepu16_epi32(_mm256_cvtps_ph(values, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
}

// One colour channel of the running average: (old * weight + new * observed_weight) / new_weight,
// rounded.
SEMFUSE_AVX2 inline __m256i blendChannel(__m256i old_channel, __m256i new_channel, __m256 weight,
                                         __m256 observed_weight, __m256 inv_new_weight) {
  const __m256 sum = _mm256_add_ps(_mm256_mul_ps(_mm256_cvtepi32_ps(old_channel), weight),
                                   _mm256_mul_ps(_mm256_cvtepi32_ps(new_channel), observed_weight));
  return _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(sum, inv_new_weight), _mm256_set1_ps(0.5f)));
}

// Lanes (bit z = lane z) -> a vector mask of all-ones lanes.
SEMFUSE_AVX2 inline __m256i laneMask(unsigned lanes) {
  const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(lanes)), bit), bit);
}

// Whether gatherPixelLabels() can address this frame's label and confidence images with int32
// byte offsets (and read 32 bits around the last label column, which needs a second column).
bool labelsGatherable(const FrameView& frame) {
  const auto rows = static_cast<std::size_t>(frame.label_height);
  return frame.label_width >= 2 && rows * frame.label_stride * sizeof(uint16_t) < static_cast<std::size_t>(INT_MAX) &&
         rows * frame.confidence_stride < static_cast<std::size_t>(INT_MAX / 4);
}

// The frame's label and confidence at the `lanes` of a column whose depth pixels are (ui, vi),
// and the lanes a rule fuses (label not ignored, 0 < confidence < inf): what applyPixelLabel()
// reads per voxel, 8 voxels at a time.
struct PixelLabels {
  __m256i observed;  // label, 32-bit lanes
  __m256 w;          // confidence
  unsigned fused_lanes;
};

SEMFUSE_AVX2 inline PixelLabels gatherPixelLabels(unsigned lanes, __m256i ui, __m256i vi, const FrameView& frame,
                                                  const KernelConfig& config) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i mask = laneMask(lanes);
  // Label pixel of each depth pixel: a shift where the sizes allow (no dependent gather), else the table.
  const __m256i lu = frame.label_col_shift >= 0
                         ? _mm256_srl_epi32(ui, _mm_cvtsi32_si128(frame.label_col_shift))
                         : _mm256_mask_i32gather_epi32(zero, frame.label_col.data(), ui, mask, 4);
  const __m256i lv = frame.label_row_shift >= 0
                         ? _mm256_srl_epi32(vi, _mm_cvtsi32_si128(frame.label_row_shift))
                         : _mm256_mask_i32gather_epi32(zero, frame.label_row.data(), vi, mask, 4);
  // A label is 16 bits, read as the low half of a 32-bit load; in the last label column that load
  // would pass the row's end, so it starts one label earlier and shifts the other one off.
  const __m256i in_last_column = _mm256_cmpeq_epi32(lu, _mm256_set1_epi32(frame.label_width - 1));
  const __m256i label_index =
      _mm256_add_epi32(_mm256_mullo_epi32(lv, _mm256_set1_epi32(static_cast<int>(frame.label_stride))), lu);
  const __m256i label_bytes =
      _mm256_add_epi32(_mm256_slli_epi32(label_index, 1), _mm256_add_epi32(in_last_column, in_last_column));
  const __m256i raw =
      _mm256_mask_i32gather_epi32(zero, reinterpret_cast<const int*>(frame.labels), label_bytes, mask, 1);
  PixelLabels px;
  px.observed = _mm256_and_si256(_mm256_srlv_epi32(raw, _mm256_and_si256(in_last_column, _mm256_set1_epi32(16))),
                                 _mm256_set1_epi32(0xFFFF));
  px.w = frame.confidence
             ? _mm256_mask_i32gather_ps(
                   _mm256_setzero_ps(), frame.confidence,
                   _mm256_add_epi32(
                       _mm256_mullo_epi32(lv, _mm256_set1_epi32(static_cast<int>(frame.confidence_stride))), lu),
                   _mm256_castsi256_ps(mask), 4)
             : _mm256_set1_ps(1.0f);
  __m256i ignored;
  if (config.ignored->onlyUnlabeled()) {
    ignored = _mm256_cmpeq_epi32(px.observed, zero);
  } else {
    const __m256i word = _mm256_mask_i32gather_epi32(zero, reinterpret_cast<const int*>(config.ignored->words()),
                                                     _mm256_srli_epi32(px.observed, 5), mask, 4);
    const __m256i bit = _mm256_and_si256(_mm256_srlv_epi32(word, _mm256_and_si256(px.observed, _mm256_set1_epi32(31))),
                                         _mm256_set1_epi32(1));
    ignored = _mm256_cmpeq_epi32(bit, _mm256_set1_epi32(1));
  }
  // 0 < w < inf is false for NaN, as the scalar w > 0 && isfinite(w).
  const __m256 usable =
      _mm256_and_ps(_mm256_cmp_ps(px.w, _mm256_setzero_ps(), _CMP_GT_OQ),
                    _mm256_cmp_ps(px.w, _mm256_set1_ps(std::numeric_limits<float>::infinity()), _CMP_LT_OQ));
  const __m256i fuse = _mm256_andnot_si256(ignored, _mm256_and_si256(mask, _mm256_castps_si256(usable)));
  px.fused_lanes = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(fuse)));
  return px;
}

// Algorithm 1 (the evidence rule) on the label half of the `lanes` of a column whose depth pixels
// are (ui, vi): what applyPixelLabel() does per voxel, 8 voxels at a time. Returns the lanes it
// changed (label neither ignored nor with a confidence that is <= 0 or not finite).
SEMFUSE_AVX2 inline unsigned fuseEvidence(__m256i& high, unsigned lanes, __m256i ui, __m256i vi, const FrameView& frame,
                                          const KernelConfig& config) {
  const PixelLabels px = gatherPixelLabels(lanes, ui, vi, frame, config);
  if (px.fused_lanes == 0) return 0;
  const __m256i zero = _mm256_setzero_si256();
  const __m256i observed = px.observed;
  const __m256 w = px.w;
  const __m256i fuse = laneMask(px.fused_lanes);
  const unsigned fused_lanes = px.fused_lanes;

  const __m256i label = _mm256_and_si256(high, _mm256_set1_epi32(0xFFFF));
  const __m256 score = halvesToFloats(_mm256_srli_epi32(high, 16));
  // Nothing known yet or outvoted: take the new label; same label: build up to W_clamp; else erode.
  const __m256 take = _mm256_or_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(label, zero)),
                                   _mm256_cmp_ps(score, _mm256_setzero_ps(), _CMP_LT_OQ));
  const __m256 same = _mm256_castsi256_ps(_mm256_cmpeq_epi32(label, observed));
  const __m256 kept_score = _mm256_blendv_ps(
      _mm256_sub_ps(score, w), _mm256_min_ps(_mm256_add_ps(score, w), _mm256_set1_ps(config.max_score)), same);
  const __m256 new_score = _mm256_blendv_ps(kept_score, w, take);
  const __m256i new_label = _mm256_blendv_epi8(label, observed, _mm256_castps_si256(take));
  const __m256i new_high = _mm256_or_si256(new_label, _mm256_slli_epi32(floatsToHalves(new_score), 16));
  high = _mm256_blendv_epi8(high, new_high, fuse);
  return fused_lanes;
}

// The top-5 rules' common case, applyLabelRule()'s shortcut, 8 voxels at a time: on the lanes
// whose voxel has no runner-up and sees its leader again (or its first label), the leader's score
// grows by the increment up to the clamp, with the scalar code's arithmetic. Updates `high` on
// those lanes, counts them in `labeled`, and returns the other fused lanes, which go through
// applyPixelLabel() one by one (fused: label not ignored, usable confidence; the rest are left as
// they are, as applyPixelLabel() leaves them).
SEMFUSE_AVX2 inline unsigned topLabelsShortcut(__m256i& high, const PackedLabelSidecar* sidecars, unsigned lanes,
                                               __m256i ui, __m256i vi, const FrameView& frame,
                                               const KernelConfig& config, std::size_t& labeled) {
  const PixelLabels px = gatherPixelLabels(lanes, ui, vi, frame, config);
  if (px.fused_lanes == 0) return 0;
  const LabelRuleConfig& rule = config.label_rule;
  const __m256 zero = _mm256_setzero_ps();
  __m256 increment = _mm256_set1_ps(1.0f);  // majority
  if (rule.rule == LabelRule::kBayes) {
    // bayesIncrementFast: the table interpolated at min(w, 1) * steps, its last entry at w = 1.
    const float* table = rule.bayes_increments->data();
    const __m256 x =
        _mm256_mul_ps(_mm256_min_ps(px.w, _mm256_set1_ps(1.0f)), _mm256_set1_ps(static_cast<float>(kBayesTableSteps)));
    const __m256i step = _mm256_cvttps_epi32(x);
    const __m256i inner = _mm256_min_epi32(step, _mm256_set1_epi32(kBayesTableSteps - 1));
    const __m256 fused = _mm256_castsi256_ps(laneMask(px.fused_lanes));
    const __m256 below = _mm256_mask_i32gather_ps(zero, table, inner, fused, 4);
    const __m256 above = _mm256_mask_i32gather_ps(zero, table + 1, inner, fused, 4);
    const __m256 between =
        _mm256_add_ps(below, _mm256_mul_ps(_mm256_sub_ps(x, _mm256_cvtepi32_ps(inner)), _mm256_sub_ps(above, below)));
    const __m256 at_end = _mm256_castsi256_ps(_mm256_cmpgt_epi32(step, _mm256_set1_epi32(kBayesTableSteps - 1)));
    increment = _mm256_blendv_ps(between, _mm256_set1_ps(table[kBayesTableSteps]), at_end);
  }
  const __m256i zero_i = _mm256_setzero_si256();
  const __m256i label = _mm256_and_si256(high, _mm256_set1_epi32(0xFFFF));
  const __m256 score = halvesToFloats(_mm256_srli_epi32(high, 16));
  const auto* sidecar_words = reinterpret_cast<const __m256i*>(sidecars);
  const auto no_runner_up = static_cast<unsigned>(
      _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_loadu_si256(sidecar_words), zero_i))) |
      (_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_loadu_si256(sidecar_words + 1), zero_i)))
       << 4));
  const __m256i unlabeled = _mm256_cmpeq_epi32(label, zero_i);
  const __m256 leader_again = _mm256_and_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(label, px.observed)),
                                            _mm256_cmp_ps(score, zero, _CMP_GE_OQ));
  const __m256 in_sidecar_range =
      _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(kMaxRunnerUpLabel) + 1), px.observed));
  const __m256 eligible = _mm256_and_ps(_mm256_and_ps(in_sidecar_range, _mm256_cmp_ps(increment, zero, _CMP_GT_OQ)),
                                        _mm256_or_ps(_mm256_castsi256_ps(unlabeled), leader_again));
  const unsigned shortcut = px.fused_lanes & no_runner_up & static_cast<unsigned>(_mm256_movemask_ps(eligible));
  if (shortcut != 0) {
    const __m256 top = _mm256_blendv_ps(_mm256_add_ps(score, increment), increment, _mm256_castsi256_ps(unlabeled));
    const __m256 clamp = _mm256_set1_ps(rule.max_score);
    const __m256 new_score =
        _mm256_blendv_ps(top, _mm256_sub_ps(top, _mm256_sub_ps(top, clamp)), _mm256_cmp_ps(top, clamp, _CMP_GT_OQ));
    const __m256i new_high = _mm256_or_si256(px.observed, _mm256_slli_epi32(floatsToHalves(new_score), 16));
    high = _mm256_blendv_epi8(high, new_high, laneMask(shortcut));
    labeled += static_cast<std::size_t>(__builtin_popcount(shortcut));
  }
  return px.fused_lanes & ~shortcut;
}

template <bool kGeometry, bool kColor, bool kLabels>
SEMFUSE_AVX2 KernelCounts updateLeaf(const LeafPair& leaf, const FrameView& frame, const KernelConfig& config) {
  KernelCounts counts;
  PackedVoxel* voxels = leaf.geometry->buffer().data();
  PackedColor* colors = kColor ? leaf.color->buffer().data() : nullptr;
  auto& active = leaf.geometry->getValueMask();
  const LeafInCamera cam = leafInCamera(*leaf.geometry, frame, config.voxel_size);

  const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
  // The scalar kernel's per-voxel products step_z * z, computed once for the 8 lanes.
  const __m256 dz_x = _mm256_mul_ps(_mm256_set1_ps(cam.step_z.x()), lane);
  const __m256 dz_y = _mm256_mul_ps(_mm256_set1_ps(cam.step_z.y()), lane);
  const __m256 dz_z = _mm256_mul_ps(_mm256_set1_ps(cam.step_z.z()), lane);
  const __m256 fx = _mm256_set1_ps(frame.fx), fy = _mm256_set1_ps(frame.fy);
  const __m256 cx = _mm256_set1_ps(frame.cx), cy = _mm256_set1_ps(frame.cy);
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f);
  const __m256 u_min = _mm256_set1_ps(-0.5f), v_min = u_min;
  const __m256 u_max = _mm256_set1_ps(static_cast<float>(frame.width) - 0.5f);
  const __m256 v_max = _mm256_set1_ps(static_cast<float>(frame.height) - 0.5f);
  const __m256 min_depth = _mm256_set1_ps(frame.min_depth), max_depth = _mm256_set1_ps(frame.max_depth);
  const __m256 truncation = _mm256_set1_ps(config.truncation);
  const __m256 min_sdf = _mm256_set1_ps(-config.truncation);
  const __m256 max_weight = _mm256_set1_ps(config.max_weight);
  const __m256 dropoff_start = _mm256_set1_ps(config.dropoff_start);
  const __m256 dropoff_per_metre = _mm256_set1_ps(config.dropoff_per_metre);
  const __m256 min_observation_weight = _mm256_set1_ps(kMinObservationWeight);
  const __m256i depth_stride = _mm256_set1_epi32(static_cast<int>(frame.depth_stride));
  const __m256i color_stride = _mm256_set1_epi32(static_cast<int>(frame.color_stride));
  const __m256i last_column = _mm256_set1_epi32(frame.width - 1);
  const __m256i low16 = _mm256_set1_epi32(0xFFFF), byte = _mm256_set1_epi32(0xFF);
  const bool labels_gatherable = kLabels && labelsGatherable(frame);
  const LabelRuleConfig& rule = config.label_rule;
  const bool vector_evidence = labels_gatherable && rule.rule == LabelRule::kEvidence;
  const bool vector_shortcut =
      labels_gatherable && leaf.label_sidecar != nullptr &&
      (rule.rule == LabelRule::kMajority || (rule.rule == LabelRule::kBayes && rule.bayes_increments != nullptr));
  // Once per leaf, as the geometry buffer: LeafBuffer::data() checks whether it is loaded.
  PackedLabelSidecar* const sidecars = leaf.label_sidecar ? leaf.label_sidecar->buffer().data() : nullptr;

  for (int x = 0; x < kLeafDim; ++x) {
    uint64_t active_bits = 0;
    for (int y = 0; y < kLeafDim; ++y) {
      const Eigen::Vector3f p = columnStart(cam, x, y);
      const int row_offset = (x << 6) | (y << 3);
      // Projection, exactly the scalar kernel's expression tree: u = fx * (px + sx * z) / cz + cx.
      const __m256 cz = _mm256_add_ps(_mm256_set1_ps(p.z()), dz_z);
      const __m256 inv_z = _mm256_div_ps(one, cz);
      const __m256 u =
          _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(fx, _mm256_add_ps(_mm256_set1_ps(p.x()), dz_x)), inv_z), cx);
      const __m256 v =
          _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(fy, _mm256_add_ps(_mm256_set1_ps(p.y()), dz_y)), inv_z), cy);
      // Ordered compares: NaN (cz = 0) is outside, as in the scalar code.
      const __m256 in_image = _mm256_and_ps(
          _mm256_and_ps(_mm256_cmp_ps(cz, zero, _CMP_GT_OQ),
                        _mm256_and_ps(_mm256_cmp_ps(u, u_min, _CMP_GE_OQ), _mm256_cmp_ps(u, u_max, _CMP_LT_OQ))),
          _mm256_and_ps(_mm256_cmp_ps(v, v_min, _CMP_GE_OQ), _mm256_cmp_ps(v, v_max, _CMP_LT_OQ)));
      if (_mm256_movemask_ps(in_image) == 0) continue;
      const __m256i ui = _mm256_cvttps_epi32(_mm256_and_ps(_mm256_add_ps(u, half), in_image));
      const __m256i vi = _mm256_cvttps_epi32(_mm256_and_ps(_mm256_add_ps(v, half), in_image));
      const __m256i pixel = _mm256_add_epi32(_mm256_mullo_epi32(vi, depth_stride), ui);
      const __m256 d = _mm256_mask_i32gather_ps(zero, frame.depth, pixel, in_image, 4);
      const __m256 sdf = _mm256_sub_ps(d, cz);
      __m256 update = _mm256_and_ps(
          _mm256_and_ps(in_image, _mm256_cmp_ps(sdf, min_sdf, _CMP_GE_OQ)),  // not far behind the surface
          _mm256_and_ps(_mm256_cmp_ps(d, min_depth, _CMP_GE_OQ), _mm256_cmp_ps(d, max_depth, _CMP_LE_OQ)));
      if (_mm256_movemask_ps(update) == 0) continue;

      PackedVoxel* column = voxels + row_offset;
      ColumnVoxels bits = loadColumn(column);
      if (kGeometry) {
        const __m256 weight = halvesToFloats(_mm256_srli_epi32(bits.low, 16));
        const __m256 observed = _mm256_min_ps(sdf, truncation);
        // observationWeight, in the same order of operations.
        const __m256 observed_weight = _mm256_min_ps(
            one,
            _mm256_max_ps(min_observation_weight,
                          _mm256_add_ps(one, _mm256_mul_ps(_mm256_add_ps(sdf, dropoff_start), dropoff_per_metre))));
        const __m256 new_weight = _mm256_add_ps(weight, observed_weight);
        const __m256 inv_new_weight = _mm256_div_ps(one, new_weight);
        const __m256 old_tsdf = halvesToFloats(_mm256_and_si256(bits.low, low16));
        const __m256 tsdf = _mm256_mul_ps(
            _mm256_add_ps(_mm256_mul_ps(old_tsdf, weight), _mm256_mul_ps(observed, observed_weight)), inv_new_weight);
        const __m256i new_low = _mm256_or_si256(
            floatsToHalves(tsdf), _mm256_slli_epi32(floatsToHalves(_mm256_min_ps(new_weight, max_weight)), 16));
        bits.low = _mm256_blendv_epi8(bits.low, new_low, _mm256_castps_si256(update));
        if (kColor) {
          // The pixel's R, G, B are bytes 0-2 of a 32-bit load at 3 * u; in the last column that
          // load would pass the row's end, so it starts one byte earlier and shifts the byte off.
          const __m256i in_last_column = _mm256_cmpeq_epi32(ui, last_column);
          const __m256i rgb_offset = _mm256_add_epi32(
              _mm256_add_epi32(_mm256_mullo_epi32(vi, color_stride), _mm256_mullo_epi32(ui, _mm256_set1_epi32(3))),
              in_last_column);  // -1 there
          const __m256i rgb_raw =
              _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), reinterpret_cast<const int*>(frame.color), rgb_offset,
                                          _mm256_castps_si256(update), 1);
          const __m256i rgb = _mm256_srlv_epi32(rgb_raw, _mm256_and_si256(in_last_column, _mm256_set1_epi32(8)));
          PackedColor* color_column = colors + row_offset;
          const __m256i old = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(color_column));
          const __m256i r = blendChannel(_mm256_and_si256(_mm256_srli_epi32(old, 16), byte),
                                         _mm256_and_si256(rgb, byte), weight, observed_weight, inv_new_weight);
          const __m256i g =
              blendChannel(_mm256_and_si256(_mm256_srli_epi32(old, 8), byte),
                           _mm256_and_si256(_mm256_srli_epi32(rgb, 8), byte), weight, observed_weight, inv_new_weight);
          const __m256i b =
              blendChannel(_mm256_and_si256(old, byte), _mm256_and_si256(_mm256_srli_epi32(rgb, 16), byte), weight,
                           observed_weight, inv_new_weight);
          // static_cast<uint8_t> of the scalar kernel keeps the low byte.
          const __m256i blended = _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi32(_mm256_and_si256(r, byte), 16),
                                                                  _mm256_slli_epi32(_mm256_and_si256(g, byte), 8)),
                                                  _mm256_and_si256(b, byte));
          _mm256_storeu_si256(reinterpret_cast<__m256i*>(color_column),
                              _mm256_blendv_epi8(old, blended, _mm256_castps_si256(update)));
        }
      } else {
        // Late labels only refine voxels that geometry has seen (weight bits non-zero).
        const __m256i unobserved = _mm256_cmpeq_epi32(_mm256_srli_epi32(bits.low, 16), _mm256_setzero_si256());
        update = _mm256_andnot_ps(_mm256_castsi256_ps(unobserved), update);
      }
      const auto update_lanes = static_cast<unsigned>(_mm256_movemask_ps(update));
      if (update_lanes == 0) continue;
      if (kGeometry) counts.updated += static_cast<std::size_t>(__builtin_popcount(update_lanes));

      if (kLabels) {
        // |d - z| < truncation: the frame sees these voxels; the rule runs per voxel.
        const auto label_lanes =
            update_lanes & static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(sdf, truncation, _CMP_LT_OQ)));
        if (label_lanes != 0 && vector_evidence) {
          counts.labeled +=
              static_cast<std::size_t>(__builtin_popcount(fuseEvidence(bits.high, label_lanes, ui, vi, frame, config)));
        } else if (label_lanes != 0) {  // the top-5 rules, with the sidecar
          unsigned per_voxel = label_lanes;
          if (vector_shortcut)
            per_voxel =
                topLabelsShortcut(bits.high, sidecars + row_offset, label_lanes, ui, vi, frame, config, counts.labeled);
          if (per_voxel != 0) {  // the lanes the shortcut does not settle, one by one
            alignas(32) uint32_t low[kLeafDim], high[kLeafDim];
            alignas(32) int col[kLeafDim], row[kLeafDim];
            _mm256_store_si256(reinterpret_cast<__m256i*>(low), bits.low);
            _mm256_store_si256(reinterpret_cast<__m256i*>(high), bits.high);
            _mm256_store_si256(reinterpret_cast<__m256i*>(col), ui);
            _mm256_store_si256(reinterpret_cast<__m256i*>(row), vi);
            for (unsigned lanes = per_voxel; lanes != 0; lanes &= lanes - 1) {
              const int z = __builtin_ctz(lanes);
              uint64_t voxel = uint64_t{low[z]} | (uint64_t{high[z]} << 32);
              PackedLabelSidecar* sidecar = sidecars ? sidecars + (row_offset | z) : nullptr;
              if (applyPixelLabel(voxel, sidecar, frame, col[z], row[z], config)) {
                high[z] = static_cast<uint32_t>(voxel >> 32);
                ++counts.labeled;
              }
            }
            bits.high = _mm256_load_si256(reinterpret_cast<const __m256i*>(high));
          }
        }
      }
      storeColumn(column, bits);
      active_bits |= uint64_t{update_lanes} << (y << 3);
    }
    active.template getWord<uint64_t>(static_cast<openvdb::Index>(x)) |= active_bits;
  }
  return counts;
}

}  // namespace

// CPUID leaf 1 ECX bit 29 is F16C. __builtin_cpu_supports("f16c") would say the same, but clang
// (used for the fuzz build) does not know that feature name.
static bool cpuHasAvx2AndF16c() {
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (__get_cpuid(1, &eax, &ebx, &ecx, &edx) == 0) return false;
  return (ecx & bit_F16C) != 0 && __builtin_cpu_supports("avx2");
}

bool avx2KernelSupported(const FrameView& frame) {
  static const bool cpu_has_it = cpuHasAvx2AndF16c();
  // Gather offsets are int32: element offsets into the depth image, byte offsets into the colour
  // image. The last-column colour read starts one byte early, which needs a second column.
  const auto rows = static_cast<std::size_t>(frame.height);
  return cpu_has_it && frame.width >= 2 && rows * frame.depth_stride < static_cast<std::size_t>(INT_MAX) &&
         rows * frame.color_stride < static_cast<std::size_t>(INT_MAX);
}

template <bool kGeometry, bool kColor, bool kLabels>
KernelCounts updateLeafAvx2(const LeafPair& leaf, const FrameView& frame, const KernelConfig& config) {
  return updateLeaf<kGeometry, kColor, kLabels>(leaf, frame, config);
}

#else  // no AVX2 kernel on this platform: the dispatcher never calls it

bool avx2KernelSupported(const FrameView&) { return false; }

template <bool kGeometry, bool kColor, bool kLabels>
KernelCounts updateLeafAvx2(const LeafPair& leaf, const FrameView& frame, const KernelConfig& config) {
  return updateLeafScalar<kGeometry, kColor, kLabels>(leaf, frame, config);
}

#endif

template KernelCounts updateLeafAvx2<true, true, true>(const LeafPair&, const FrameView&, const KernelConfig&);
template KernelCounts updateLeafAvx2<true, true, false>(const LeafPair&, const FrameView&, const KernelConfig&);
template KernelCounts updateLeafAvx2<true, false, true>(const LeafPair&, const FrameView&, const KernelConfig&);
template KernelCounts updateLeafAvx2<true, false, false>(const LeafPair&, const FrameView&, const KernelConfig&);
template KernelCounts updateLeafAvx2<false, false, true>(const LeafPair&, const FrameView&, const KernelConfig&);

}  // namespace semfuse::volume::detail
