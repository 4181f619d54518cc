#pragma once
// Whether two OpenVDB grids hold the same thing: the same leaves, each with the same active mask
// and the same values, active or not (a map caught up from changes against one fused directly,
// one integration kernel against another). The first few differing voxels are reported.
#include <cstddef>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

namespace semfuse::testing {

// Both null, or both grids with identical leaves; `what` names the grid in failures.
template <class Grid>
void expectSameGrid(const Grid* a, const Grid* b, const char* what) {
  ASSERT_EQ(a == nullptr, b == nullptr) << what;
  if (!a) return;
  ASSERT_EQ(a->tree().leafCount(), b->tree().leafCount()) << what;
  EXPECT_EQ(a->tree().activeVoxelCount(), b->tree().activeVoxelCount()) << what;
  openvdb::tree::ValueAccessor<const typename Grid::TreeType> others(b->tree());
  std::size_t differing = 0;
  for (auto leaf = a->tree().cbeginLeaf(); leaf; ++leaf) {
    const auto* other = others.probeConstLeaf(leaf->origin());
    ASSERT_NE(other, nullptr) << what << ": leaf " << leaf->origin() << " missing";
    EXPECT_EQ(leaf->getValueMask(), other->getValueMask()) << what << ": active mask of leaf " << leaf->origin();
    for (openvdb::Index i = 0; i < Grid::TreeType::LeafNodeType::SIZE; ++i)
      if (!(leaf->getValue(i) == other->getValue(i)) && ++differing <= 5)
        ADD_FAILURE() << what << ": voxel " << leaf->offsetToGlobalCoord(i) << " " << leaf->getValue(i) << " vs "
                      << other->getValue(i);
  }
  EXPECT_EQ(differing, 0u) << what;
}

}  // namespace semfuse::testing
