// The client's joining of mesh chunks (client/src/mesh_assembly.*): chunks that do not add up,
// and sizes announced in a reply that must not make the client allocate them.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>

#include "mesh_assembly.hpp"

namespace semfuse::client::detail {
namespace {

MeshChunk chunk(uint64_t mesh_id, uint32_t index, uint32_t count, uint64_t total, const std::string& bytes) {
  MeshChunk chunk;
  chunk.mesh_id = mesh_id;
  chunk.chunk_index = index;
  chunk.chunk_count = count;
  chunk.total_bytes = total;
  chunk.ply.assign(bytes.begin(), bytes.end());
  return chunk;
}

TEST(MeshAssembly, MeshChunksJoinInOrder) {
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(chunk(9, 0, 2, 7, "ply\n"), 0).ok());
  EXPECT_EQ(assembly.chunkCount(), 2u);
  EXPECT_EQ(assembly.meshId(), 9u);
  ASSERT_TRUE(assembly.add(chunk(9, 1, 2, 7, "end"), 1).ok());
  auto mesh = std::move(assembly).finish();
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  EXPECT_EQ(std::string(mesh.value().ply.begin(), mesh.value().ply.end()), "ply\nend");
}

TEST(MeshAssembly, MeshChunksThatDoNotBelongAreRefused) {
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(chunk(9, 0, 2, 7, "ply\n"), 0).ok());
  const Status wrong_mesh = assembly.add(chunk(10, 1, 2, 7, "end"), 1);
  ASSERT_FALSE(wrong_mesh.ok());
  EXPECT_NE(wrong_mesh.error().find("of mesh 10"), std::string::npos) << wrong_mesh.error();
  const Status overflow = assembly.add(chunk(9, 1, 2, 7, "end and more"), 1);
  ASSERT_FALSE(overflow.ok());
  EXPECT_NE(overflow.error().find("more than the 7 bytes"), std::string::npos) << overflow.error();
  const Status out_of_order = assembly.add(chunk(9, 0, 2, 7, "ply\n"), 0);
  ASSERT_FALSE(out_of_order.ok());
  EXPECT_NE(out_of_order.error().find("in order"), std::string::npos) << out_of_order.error();
  auto incomplete = std::move(assembly).finish();
  ASSERT_FALSE(incomplete.ok());
  EXPECT_NE(incomplete.error().find("1 of 2 chunks"), std::string::npos) << incomplete.error();
}

TEST(MeshAssembly, AnAbsurdAnnouncedMeshSizeIsNotAllocated) {
  // A reply announcing 2^60 bytes in one 4-byte chunk once made the client reserve them
  // (std::bad_alloc thrown out of MapClient::mesh).
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(chunk(1, 0, 1, uint64_t{1} << 60, "ply\n"), 0).ok());
  auto mesh = std::move(assembly).finish();
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().find("server announced"), std::string::npos) << mesh.error();
}

TEST(MeshAssembly, ManyAnnouncedChunksDoNotMakeTheClientReserveGigabytes) {
  // 2^32 - 1 chunks of 64 bytes and a total to match: the first fix still reserved 4 GB (fuzzer).
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(chunk(1, 0, UINT32_MAX, uint64_t{64} * UINT32_MAX, std::string(64, 'x')), 0).ok());
  EXPECT_EQ(assembly.chunkCount(), UINT32_MAX);
  EXPECT_LE(assembly.reservedBytes(), kMaxMeshReserveBytes);
  EXPECT_GE(assembly.reservedBytes(), 64u);
}

}  // namespace
}  // namespace semfuse::client::detail
