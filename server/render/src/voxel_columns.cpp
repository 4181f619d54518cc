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
        for (int z = 0; z < kTop; ++z) readVoxel(static_cast<uint64_t>(source.low[z]), z, brick_column, seen, below);
      } else {
        std::fill(brick_column, brick_column + kTop, 0.0f);
      }
      finishColumn(source, brick_column, seen, below, x, y, columns);
    }
}

}  // namespace detail
}  // namespace semfuse::render
