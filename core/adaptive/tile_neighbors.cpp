#include "core/adaptive/tile_neighbors.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>

#include "core/math/dyadic.h"

namespace tessera {

namespace {

// t (scale kLineScale) of root side coordinate s (scale kRootScale) and back.
int64_t toLine(const SideLine& line, int64_t s) {
  return (line.origin ? kLineScale : 0) + line.sign * (line.halves == 1 ? 2 * s : s);
}
int64_t toSide(const SideLine& line, int64_t t) {
  const int64_t along = line.sign * (t - (line.origin ? kLineScale : 0));
  return line.halves == 1 ? along / 2 : along;
}

}  // namespace

TileNeighbors::TileNeighbors(const RootSeams& seams, const RootTiles& tiles)
    : seams_(seams), tiles_(tiles), own_(tiles.size()), roots_(own_) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(tiles.size()), 64), [&](const auto& range) {
    for (uint32_t r = range.begin(); r != range.end(); ++r) roots_[r].index(tiles[r]);
  });
}

TileNeighbors::TileNeighbors(const RootSeams& seams, const RootTiles& tiles, std::vector<RootTileIndex>& roots)
    : seams_(seams), tiles_(tiles), roots_(roots) {}

void RootTileIndex::index(const std::vector<Tile>& tiles) {
  entries_.clear();
  for (uint32_t t = 0; t < tiles.size(); ++t) {
    // A rectangle (core/adaptive/tile_rectangles.h) under each of its squares.
    const Tile& tile = tiles[t];
    for (uint64_t iy = tile.iy; iy < tile.iyEnd(); ++iy) {
      for (uint64_t ix = tile.ix; ix < tile.ixEnd(); ++ix) entries_.push_back({tile.level, ix, iy, t});
    }
  }
  std::sort(entries_.begin(), entries_.end());
}

uint32_t RootTileIndex::covering(int level, uint64_t ix, uint64_t iy) const {
  for (int l = level; l >= 0; --l) {
    const Entry key{l, ix >> (level - l), iy >> (level - l), 0};
    const auto found = std::lower_bound(entries_.begin(), entries_.end(), key);
    if (found != entries_.end() && found->level == l && found->ix == key.ix && found->iy == key.iy) return found->tile;
  }
  return UINT32_MAX;
}

// The tile across: points inside our side come from a smaller tile (its corner), from cells
// shorter than the side (the densest-first rule fills the gap), or from a strip or a cell-wise
// tile, which keep their own points (tile_stitching.h).
bool RootTileIndex::acrossGivesPoints(const std::vector<Tile>& tiles, int level, uint64_t ix, uint64_t iy, int side,
                                      int64_t a, int64_t b) const {
  const uint32_t t = covering(level, ix, iy);
  if (t == UINT32_MAX) return true;
  const Tile& n = tiles[t];
  const bool alongU = side == 0 || side == 2;
  const int cells = alongU ? n.ru : n.rv;
  const int64_t sideLength = rootCoordinate(n.levelAlong(side), 1);
  // Its cell, sideLength / cells, against our side, b − a.
  if (__int128(sideLength) < __int128(b - a) * cells) return true;
  // The first point it keeps past a: at origin + j·sideLength/kept.
  const int kept = n.keptIntervals(side);
  if (kept == 1) return false;
  const int64_t origin = rootCoordinate(n.levelAlong(side), n.indexAlong(side));
  const __int128 j = (__int128(a - origin) * kept) / sideLength + 1;
  return j < kept && __int128(origin) * kept + j * sideLength < __int128(b) * kept;
}

namespace {

// Whether `gets` holds for any square of side k of `tile` seen as a one-cell tile's: the tile's
// own square, or for a cell-wise tile (which keeps its own points) each of its cells along the
// side, as the one-cell tile it was.
template <class Gets>
bool anySideSquare(const Tile& tile, int side, const Gets& gets) {
  if (!tile.cellwise) return gets(tile.level, tile.ix, tile.iy);
  const int cells = tile.ru, depth = __builtin_ctz(unsigned(cells));
  const uint64_t x0 = tile.ix << depth, y0 = tile.iy << depth, last = uint64_t(cells) - 1;
  for (uint64_t c = 0; c < uint64_t(cells); ++c) {
    const uint64_t x = x0 + (side == 0 || side == 2 ? c : side == 1 ? last : 0);
    const uint64_t y = y0 + (side == 1 || side == 3 ? c : side == 2 ? last : 0);
    if (gets(tile.level + depth, x, y)) return true;
  }
  return false;
}

}  // namespace

bool RootTileIndex::innerSideGetsPoints(const std::vector<Tile>& tiles, uint32_t t, int side) const {
  return anySideSquare(tiles[t], side, [&](int level, uint64_t ix, uint64_t iy) {
    const bool alongU = side == 0 || side == 2;
    const int64_t a = rootCoordinate(level, alongU ? ix : iy), b = rootCoordinate(level, (alongU ? ix : iy) + 1);
    const uint64_t nx = side == 1 ? ix + 1 : side == 3 ? ix - 1 : ix;
    const uint64_t ny = side == 2 ? iy + 1 : side == 0 ? iy - 1 : iy;
    return acrossGivesPoints(tiles, level, nx, ny, side ^ 2, a, b);
  });
}

bool TileNeighbors::sideGetsPoints(uint32_t root, uint32_t index, int side) const {
  const Tile& tile = tiles_[root][index];
  if (!tile.onRootSide(side)) return roots_[root].innerSideGetsPoints(tiles_[root], index, side);
  return anySideSquare(tile, side, [&](int level, uint64_t ix, uint64_t iy) {
    return squareSideGetsPoints(root, level, ix, iy, side);
  });
}

bool TileNeighbors::squareSideGetsPoints(uint32_t root, int level, uint64_t ix, uint64_t iy, int side) const {
  const bool alongU = side == 0 || side == 2;
  const int64_t a = rootCoordinate(level, alongU ? ix : iy), b = rootCoordinate(level, (alongU ? ix : iy) + 1);
  // Across a base edge or spoke: the roots on the same line, where they overlap our side.
  const RootSeams::Span& ours = seams_.own[4 * size_t(root) + side];
  int64_t ta = toLine(ours.line, a), tb = toLine(ours.line, b);
  if (tb < ta) std::swap(ta, tb);
  for (uint32_t i = seams_.first[4 * size_t(root) + side]; i < seams_.first[4 * size_t(root) + side + 1]; ++i) {
    const RootSeams::Span& other = seams_.spans[i];
    const int64_t lo = std::max(ta, other.t0), hi = std::min(tb, other.t1);
    if (hi <= lo) continue;
    // Another root's side ends inside ours: its corner is a point beside ours.
    if (lo > ta || hi < tb) return true;
    int64_t sa = toSide(other.line, lo), sb = toSide(other.line, hi);
    if (sb < sa) std::swap(sa, sb);
    const int64_t length = sb - sa;
    const int otherLevel = kRootBits - (63 - __builtin_clzll(uint64_t(length)));
    const uint64_t i2 = uint64_t(sa / length), end = (uint64_t(1) << otherLevel) - 1;
    const int k = other.side;
    const uint64_t nx = k == 1 ? end : k == 3 ? 0 : i2, ny = k == 2 ? end : k == 0 ? 0 : i2;
    if (tiles_[other.root].empty()) continue;  // a hole
    if (roots_[other.root].acrossGivesPoints(tiles_[other.root], otherLevel, nx, ny, k, sa, sb)) return true;
  }
  return false;
}

}  // namespace tessera
