#include "core/adaptive/tile_rectangles.h"

#include <algorithm>
#include <tuple>

namespace tessera {

namespace {

bool mergeable(const Tile& t) {
  return !t.pendingPair && !t.faceTriangle && t.cellDiagonals == 0;
}

// Triangulated cell by cell (one-cell tiles, strips, cell-wise tiles) or as a grid with zips.
bool cellType(const Tile& t) {
  return t.ru == 1 || t.rv == 1 || t.cellwise;
}

// A mergeable tile in a pass along one axis: what its partner must share (size, rates, kind and
// diagonal, packed), its position across the axis, and along it.
struct Entry {
  uint64_t key, across, along;
  uint32_t tile;
  friend bool operator<(const Entry& a, const Entry& b) {
    return std::tie(a.key, a.across, a.along) < std::tie(b.key, b.across, b.along);
  }
};

Entry entryOf(const Tile& t, uint32_t index, bool alongU) {
  const uint64_t key = uint64_t(t.level) << 40 | uint64_t(t.spanU) << 34 | uint64_t(t.spanV) << 28 |
                       uint64_t(t.ru) << 20 | uint64_t(t.rv) << 12 | uint64_t(cellType(t)) << 8 |
                       t.diagonal;
  return {key, alongU ? t.iy : t.ix, alongU ? t.ix : t.iy, index};
}

// The deepest tree node holding the rectangle: the square at the level of its longer side
// holds it (the rectangle is aligned), and a node holding one of its halves may already.
NodeSquare holder(const SurfaceTree& tree, const NodeSquare& top, const Tile& half,
                  const Tile& merged) {
  const int level = merged.level - std::max(merged.spanU, merged.spanV);
  if (half.node.level <= level) return half.node;
  NodeSquare node = top;
  while (node.level < level && !tree.nodes[node.node].isLeaf()) {
    const int d = merged.level - node.level - 1;
    node = node.child(tree, int((merged.ix >> d) & 1) | int(((merged.iy >> d) & 1) << 1));
  }
  return node;
}

// One pass along one axis: each aligned pair, left (or lower) half first, merged into the first.
bool mergePairs(const SurfaceTree& tree, const NodeSquare& top, bool alongU,
                std::vector<Tile>& tiles, std::vector<Entry>& entries, std::vector<uint8_t>& gone) {
  entries.clear();
  for (uint32_t t = 0; t < tiles.size(); ++t) {
    if (!gone[t] && mergeable(tiles[t])) entries.push_back(entryOf(tiles[t], t, alongU));
  }
  std::sort(entries.begin(), entries.end());
  bool merged = false;
  for (size_t i = 0; i + 1 < entries.size(); ++i) {
    const Entry &a = entries[i], &b = entries[i + 1];
    Tile& low = tiles[a.tile];
    const int span = alongU ? low.spanU : low.spanV;
    const int rate = 2 * (alongU ? low.ru : low.rv);
    if (a.key != b.key || a.across != b.across || (a.along >> span) % 2 != 0 ||
        b.along != a.along + (uint64_t(1) << span) || rate > kMaxTileRate) {
      continue;
    }
    const Tile& high = tiles[b.tile];
    Tile tile = low;
    (alongU ? tile.spanU : tile.spanV) += 1;
    (alongU ? tile.ru : tile.rv) = rate;
    tile.cellwise = cellType(low);
    tile.bound = std::max(low.bound, high.bound);
    tile.tolerance = std::min(low.tolerance, high.tolerance);
    tile.node = holder(tree, top, low, tile);
    low = tile;
    gone[b.tile] = 1;
    merged = true;
    ++i;
  }
  return merged;
}

}  // namespace

void mergeRectangles(const SurfaceTree& tree, const NodeSquare& top, std::vector<Tile>& tiles) {
  if (std::count_if(tiles.begin(), tiles.end(), mergeable) < 2) return;
  // Scratch kept per thread: planning calls this for every root it plans or plans again.
  thread_local std::vector<uint8_t> gone;
  thread_local std::vector<Entry> entries;
  gone.assign(tiles.size(), 0);
  for (bool any = true; any;) {
    any = mergePairs(tree, top, true, tiles, entries, gone);
    any = mergePairs(tree, top, false, tiles, entries, gone) || any;
  }
  size_t kept = 0;
  for (size_t t = 0; t < tiles.size(); ++t) {
    if (!gone[t]) tiles[kept++] = tiles[t];
  }
  tiles.resize(kept);
}

}  // namespace tessera
