// Which tile sides will get points beside their corners once seams are stitched, without
// stitching (docs/ADAPTIVE.md §3): a side does when a smaller tile meets it, when the tile across
// has cells along it shorter than the side, or when the tile across is a strip or a cell-wise
// tile, whose own points it must keep, and one falls inside the side (tile_stitching.h's rules).
// Lets planning settle the one-cell tiles it planned on their corners' bound alone: the sides
// inside a root as soon as the root is planned (RootTileIndex), the others in cheap rounds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/surface/root_seams.h"
#include "core/surface/surface_tree.h"

namespace tessera {

// One root's tiles indexed by square (a rectangle under each of its squares), for the questions
// about sides inside the root, which only its own tiles answer.
class RootTileIndex {
 public:
  void index(const std::vector<Tile>& tiles);
  // Emptied, its room kept (core/adaptive/plan_scratch.h); returns the bytes held.
  size_t clearKeepingRoom() {
    const size_t bytes = entries_.capacity() * sizeof(Entry);
    entries_.clear();
    return bytes;
  }
  // The tile covering square (level, ix, iy), UINT32_MAX when smaller tiles do.
  uint32_t covering(int level, uint64_t ix, uint64_t iy) const;
  // Whether the tile across square (level, ix, iy)'s side `side` puts points strictly inside that
  // side, which runs over [a, b] (root coordinates, scale kRootScale).
  bool acrossGivesPoints(const std::vector<Tile>& tiles, int level, uint64_t ix, uint64_t iy, int side, int64_t a,
                         int64_t b) const;
  // Whether side k of tiles[t], a side inside the root, will get points beside its own.
  bool innerSideGetsPoints(const std::vector<Tile>& tiles, uint32_t t, int side) const;

 private:
  struct Entry {
    int level;
    uint64_t ix, iy;
    uint32_t tile;
    friend bool operator<(const Entry& a, const Entry& b) {
      return std::tie(a.level, a.ix, a.iy) < std::tie(b.level, b.ix, b.iy);
    }
  };
  std::vector<Entry> entries_;  // sorted by (level, ix, iy)
};

class TileNeighbors {
 public:
  // Every root indexed here, or (the second form) as planning indexed them.
  TileNeighbors(const RootSeams& seams, const RootTiles& tiles);
  TileNeighbors(const RootSeams& seams, const RootTiles& tiles, std::vector<RootTileIndex>& roots);
  // The roots' indexes, which planning keeps up to date as it plans squares again.
  std::vector<RootTileIndex>& roots() { return roots_; }
  // Whether side k of tiles[root][tile] will get points beside its corners (beside its own grid
  // points, for a cell-wise tile).
  bool sideGetsPoints(uint32_t root, uint32_t tile, int side) const;

 private:
  // Side k of square (level, ix, iy) of `root`, a side on the root's boundary, as a one-cell tile's.
  bool squareSideGetsPoints(uint32_t root, int level, uint64_t ix, uint64_t iy, int side) const;

  const RootSeams& seams_;
  const RootTiles& tiles_;
  std::vector<RootTileIndex> own_;     // the first form's
  std::vector<RootTileIndex>& roots_;  // own_, or planning's
};

}  // namespace tessera
