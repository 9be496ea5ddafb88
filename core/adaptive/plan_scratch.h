// Planning's per-root room kept from call to call (core/base/scratch_pool.h). Every root's tiles and
// its index are vectors filled by whichever core plans the root; made fresh each call they were
// 240 of the creased torus's 353 allocations a call at 1e-3, grown on the planning cores and freed
// on the calling one, which costs most with the cores far apart (docs/ADAPTIVE.md §8).
#pragma once

#include <memory>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/adaptive/tile_neighbors.h"
#include "core/base/scratch_pool.h"

namespace tessera {

struct PlanScratch {
  RootTiles tiles;
  std::vector<RootTileIndex> indexes;

  // Every root's tiles and index emptied, their room kept; returns the bytes held.
  size_t clearKeepingRoom() {
    size_t bytes = 0;
    for (std::vector<Tile>& root : tiles) {
      bytes += root.capacity() * sizeof(Tile);
      root.clear();
    }
    for (RootTileIndex& index : indexes) bytes += index.clearKeepingRoom();
    return bytes;
  }
};

// Over 16 MB (a request of a hundred thousand tiles), one is freed instead.
inline ScratchPool<PlanScratch>& planScratchPool() {
  static ScratchPool<PlanScratch> pool(size_t(16) << 20);
  return pool;
}

// One PlanScratch for a call, given back when the call ends (or throws).
class PlanScratchLease {
 public:
  PlanScratchLease() : scratch_(planScratchPool().take()) {}
  PlanScratchLease(const PlanScratchLease&) = delete;
  PlanScratchLease& operator=(const PlanScratchLease&) = delete;
  ~PlanScratchLease() { planScratchPool().give(std::move(scratch_)); }
  PlanScratch* operator->() const { return scratch_.get(); }

 private:
  std::unique_ptr<PlanScratch> scratch_;
};

}  // namespace tessera
