// Adaptive planning (docs/ADAPTIVE.md §3): per root, a cut of the surface tree into tiles, each
// a square of its root tessellated as an ru × rv grid, with ru, rv and the cut chosen so that a
// proven bound on the distance between every triangle the tile yields and the exact limit
// surface stays within the tile's ε, for the fewest triangles the bounds allow. Tiles may span
// many pieces (a coarse node's curvature bound covers them all); below a leaf piece they are
// its de Casteljau quadrants.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/math/dyadic.h"
#include "core/request/tessellation_options.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree.h"

namespace tessera {

struct Tile {
  NodeSquare node;  // the deepest tree node holding the tile (a leaf when the tile lies below one)
  int level = 0;    // the tile's own square in its root
  uint64_t ix = 0, iy = 0;
  int ru = 1, rv = 1;   // cells along u and v
  float bound = 0;      // proven distance to the limit surface of the triangles it yields
  float tolerance = 0;  // the ε it was planned for
  // A one-cell tile planned on the bound through its corners alone: once its sides' points are
  // known, `bound` must add the bow of every side that got points beside its corners.
  bool pendingPair = false;
  float sideBow[4] = {0, 0, 0, 0};
  // A pending tile's grid without the shortcut, when planning found it small enough to be emitted
  // as it is (no split could save enough): what planning the tile again makes, so a tile that fails
  // its check takes it in place (settledRu = 0: none; planned again from its node).
  uint8_t settledRu = 0, settledRv = 0, settledDiagonal = 0;
  float settledBound = 0;
  // A pending tile's sides inside its root that get points beside its own (bit k: side k), as
  // planning found them (its root's own tiles decide those; the rounds ask only about the rest).
  uint8_t innerSidesWithPoints = 0;
  // Four sibling one-cell tiles (or cell-wise tiles of one rate) merged: ru = rv = 2^k cells,
  // each triangulated as the one-cell tile it was, its sides keeping their own points; `bound`
  // is the largest of theirs, and when pending, "points beside its corners" means points beside
  // its own grid points (docs/ADAPTIVE.md §6). A rectangle of such tiles (spanU, spanV below) has
  // any ru × rv.
  bool cellwise = false;
  // A one-cell tile whose bound holds only split along one diagonal (SurfaceNode::pairDiagonal):
  // 0 any, 1 + d diagonal d (0: corners 0–2, 1: corners 1–3); a cell-wise tile's cells all keep
  // it, unless cellDiagonals says otherwise.
  uint8_t diagonal = 0;
  // A cell-wise tile of at most 4 × 4 cells whose cells keep different diagonals: cell (i, j)'s
  // (as `diagonal`) in bits 2 (i + ru j) and up; 0 when every cell keeps `diagonal`.
  uint32_t cellDiagonals = 0;
  // 1 + k: the one-cell tile of sub-face k of a triangular base face whose three sub-faces are
  // tessellated together as the triangle through the face's corners, split at the middles its
  // edges keep (core/stitching/face_triangles.h); faceMiddles: its edges keep their middles whatever the
  // neighbours do. Only the flattened plan has these; sub-face 0's tile emits the triangles.
  uint8_t faceTriangle = 0;
  bool faceMiddles = false;
  // A dyadic rectangle of 2^spanU × 2^spanV squares of `level` from square (ix, iy) (aligned:
  // ix a multiple of 2^spanU, iy of 2^spanV): settled tiles of one size, rates and kind merged
  // side by side once planned (core/adaptive/tile_rectangles.h); 0 is one square.
  uint8_t spanU = 0, spanV = 0;

  // Extent along u and v, and one past the last square along each (squares of `level`).
  double width() const { return exp2i(int(spanU) - level); }
  double height() const { return exp2i(int(spanV) - level); }
  uint64_t ixEnd() const { return ix + (uint64_t(1) << spanU); }
  uint64_t iyEnd() const { return iy + (uint64_t(1) << spanV); }
  // Side k's level and its index along its axis at that level (k = 0, 2 along u; 1, 3 along v).
  int levelAlong(int k) const { return level - int(k == 0 || k == 2 ? spanU : spanV); }
  uint64_t indexAlong(int k) const { return k == 0 || k == 2 ? ix >> spanU : iy >> spanV; }
  // Inner grid point (i, j) (0 < i < ru, 0 < j < rv) in root coordinates.
  void gridPoint(int i, int j, double& u, double& v) const {
    u = (double(indexAlong(0)) + double(i) / ru) * width();
    v = (double(indexAlong(1)) + double(j) / rv) * height();
  }
  // Side k's own points that every line keeps, as the intervals they cut it into (docs/ADAPTIVE.md
  // §7): every cell's for a strip's long side and a cell-wise tile (triangulated cell by cell),
  // else its ends and, for a rectangle of grid tiles, the corners of the squares it was made of.
  int keptIntervals(int k) const {
    const bool alongU = k == 0 || k == 2;
    const int cells = alongU ? ru : rv;
    if (cellwise || (ru == 1) != (rv == 1)) return cells;
    return 1 << (alongU ? spanU : spanV);
  }
  // A pending tile's bound once it is known which sides get points beside its own (bit k: side k).
  float boundWithPoints(uint8_t sides) const {
    float bow = 0;
    for (int k = 0; k < 4; ++k) {
      if (sides >> k & 1) bow = std::max(bow, sideBow[k]);
    }
    return bound + bow;
  }
  uint8_t cellDiagonal(int i, int j) const {
    return cellDiagonals ? uint8_t(cellDiagonals >> (2 * (i + ru * j)) & 3) : diagonal;
  }
  // Whether side k (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0) lies on its root's side k.
  bool onRootSide(int k) const {
    const uint64_t end = uint64_t(1) << level;
    return k == 0 ? iy == 0 : k == 1 ? ixEnd() == end : k == 2 ? iyEnd() == end : ix == 0;
  }
};

struct AdaptivePlan {
  std::vector<Tile> tiles;             // root by root, each root's tiles in tree order
  std::vector<uint32_t> rootFirstTile;  // roots.size() + 1 entries
  double guaranteedBound = 0;          // max over tiles
  double tolerance = 0;                // the smallest ε of any tile
  int64_t gridTriangles = 0;           // Σ 2 ru rv: the triangles before stitching adds any
};

// Tiles cap their rates at this many cells a side and split beyond.
inline constexpr int kMaxTileRate = 64;

// A tile's square in its root (sorted by root).
struct TileSquare {
  uint32_t root;
  int level;
  uint64_t ix, iy;
  uint8_t sidesWithPoints = 0xF;  // bit k: side k got points beside its own (as known)
  friend bool operator<(const TileSquare& a, const TileSquare& b) { return a.root < b.root; }
};

class RootTileIndex;  // core/adaptive/tile_neighbors.h

// Plans every root into tiles[root]. One-cell tiles may be planned optimistically (pendingPair):
// the caller checks them against their neighbours (adaptive_tessellator.h) and plans the squares
// of those that fail again with replanSquares.
using RootTiles = std::vector<std::vector<Tile>>;
// With `indexes`, each root's tiles indexed there too (tile_neighbors.h), by the core that planned it.
// Throws TesseraError (kInvalidInput) for bad options (validateTessellationOptions) before any work.
void planRoots(const SurfaceTree& tree, const PatchSet& patches, const TessellationOptions& options, RootTiles& tiles,
               std::vector<RootTileIndex>* indexes = nullptr);

// Each failed pending tile (`failed` sorted by root) replaced in place by the tiles of its square
// planned without the optimistic shortcut (a merged cell-wise tile's: its quadrants unmerged, the
// shortcut kept, so that only those that fail on their own lose it next).
void replanSquares(const SurfaceTree& tree, const PatchSet& patches, const TessellationOptions& options,
                   const std::vector<TileSquare>& failed, RootTiles& tiles,
                   std::vector<RootTileIndex>* indexes = nullptr);

AdaptivePlan flattenPlan(const RootTiles& tiles);

}  // namespace tessera
