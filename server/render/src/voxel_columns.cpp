#include "voxel_columns.hpp"

#include <algorithm>
#include <atomic>

#include "semfuse/render/raycast.hpp"

namespace semfuse::render {
namespace {

std::atomic<RaycastKernel> g_kernel{detail::voxelColumnsAvx2Supported() ? RaycastKernel::kAvx2
                                                                         : RaycastKernel::kScalar};

}  // namespace

RaycastKernel raycastKernel() { return g_kernel.load(std::memory_order_relaxed); }

bool raycastKernelAvailable(RaycastKernel kernel) {
  return kernel == RaycastKernel::kScalar || detail::voxelColumnsAvx2Supported();
}

bool setRaycastKernel(RaycastKernel kernel) {
  if (!raycastKernelAvailable(kernel)) return false;
  g_kernel.store(kernel, std::memory_order_relaxed);
  return true;
}

const char* raycastKernelName(RaycastKernel kernel) { return kernel == RaycastKernel::kAvx2 ? "avx2" : "scalar"; }

namespace detail {

void readVoxelColumns(const CrossingCells::LeafCells& leaf, float* brick, VoxelColumns& columns) {
  constexpr int kSpan = VoxelColumns::kSpan, kTop = CrossingCells::kLeafDim;
  for (int x = 0; x < kSpan; ++x)
    for (int y = 0; y < kSpan; ++y) {
      const ColumnSource source = columnSource(leaf, x, y);
      float* brick_column = brick + CrossingCells::kBrickStride * x + CrossingCells::kBrickDim * y;
      unsigned seen = 0, below = 0;
      if (source.low) {
        for (int z = 0; z < kTop; ++z) {
          const auto bits = static_cast<uint64_t>(source.low[z]);
          seen |= static_cast<unsigned>((bits & 0xFFFF0000u) != 0) << z;
          below |= static_cast<unsigned>(nonPositiveBits(bits)) << z;
          brick_column[z] = volume::detail::halfValueBranchless(bits);
        }
      } else {
        std::fill(brick_column, brick_column + kTop, 0.0f);
      }
      if (source.high) {
        const auto bits = static_cast<uint64_t>(source.high[0]);
        seen |= static_cast<unsigned>((bits & 0xFFFF0000u) != 0) << kTop;
        below |= static_cast<unsigned>(nonPositiveBits(bits)) << kTop;
        brick_column[kTop] = volume::detail::halfValueBranchless(bits);
      } else {
        brick_column[kTop] = 0.0f;
      }
      columns.observed[x][y] = static_cast<uint16_t>(seen);
      columns.non_positive[x][y] = static_cast<uint16_t>(seen & below);
      columns.positive[x][y] = static_cast<uint16_t>(seen & ~below);
    }
}

}  // namespace detail
}  // namespace semfuse::render
