#include "mesh_block_store.hpp"

#include <algorithm>
#include <utility>

namespace semfuse::server {

MeshBlockStore::MeshBlockStore(uint64_t session) { header_.session = session; }

std::vector<MeshBlock> MeshBlockStore::apply(std::vector<MeshBlock> blocks) {
  std::vector<MeshBlock> changed;
  std::lock_guard lock(mutex_);
  for (MeshBlock& block : blocks) {
    auto it = blocks_.find(block.origin);
    if (it == blocks_.end()) {
      if (block.empty()) continue;
      changed.push_back(block);
      blocks_.emplace(block.origin, std::move(block));
      continue;
    }
    if (it->second.sameMesh(block)) continue;
    changed.push_back(block);
    it->second = std::move(block);
  }
  return changed;
}

void MeshBlockStore::clear(uint64_t revision) {
  std::lock_guard lock(mutex_);
  blocks_.clear();
  header_.cleared_revision = revision;
  header_.revision = std::max(header_.revision, revision);
}

void MeshBlockStore::setCurrent(uint64_t revision, uint64_t frames_integrated, double voxel_size) {
  std::lock_guard lock(mutex_);
  header_.revision = revision;
  header_.frames_integrated = frames_integrated;
  header_.voxel_size = voxel_size;
}

MapBlocksHeader MeshBlockStore::header() const {
  std::lock_guard lock(mutex_);
  return header_;
}

MapBlocksPage MeshBlockStore::page(const MapBlocksRequest& request, uint32_t default_bytes) const {
  const std::size_t budget = request.max_bytes > 0 ? request.max_bytes : default_bytes;
  MapBlocksPage page;
  std::lock_guard lock(mutex_);
  page.header = header_;
  auto it = request.resume_after ? blocks_.upper_bound(*request.resume_after) : blocks_.begin();
  std::size_t bytes = 0;
  for (; it != blocks_.end(); ++it) {
    const MeshBlock& block = it->second;
    if (block.revision <= request.since_revision) continue;
    if (block.empty() && request.since_revision == 0) continue;
    const std::size_t size = block.payloadBytes() + MeshBlock::kFramingBytes;
    if (!page.blocks.empty() && bytes + size > budget) break;
    page.blocks.push_back(block);
    page.next_after = block.origin;
    bytes += size;
  }
  page.complete = it == blocks_.end();
  return page;
}

void MeshBlockStore::visitBlocks(const std::function<void(const std::vector<const MeshBlock*>&)>& fn) const {
  std::lock_guard lock(mutex_);
  std::vector<const MeshBlock*> blocks;
  blocks.reserve(blocks_.size());
  for (const auto& [origin, block] : blocks_)
    if (!block.empty()) blocks.push_back(&block);
  fn(blocks);
}

MeshBlockStore::Totals MeshBlockStore::totals() const {
  Totals totals;
  std::lock_guard lock(mutex_);
  for (const auto& [origin, block] : blocks_) {
    if (block.empty()) continue;
    ++totals.blocks;
    totals.vertices += block.own_vertices;
    totals.triangles += block.triangleCount();
    totals.payload_bytes += block.payloadBytes();
  }
  return totals;
}

}  // namespace semfuse::server
