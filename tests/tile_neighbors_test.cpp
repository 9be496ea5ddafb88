// Which tile sides get points beside their own (core/adaptive/tile_neighbors.h, docs/ADAPTIVE.md §3), and
// the planner's promise that no pending tile is left that its own root's tiles break.
#include "core/adaptive/tile_neighbors.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

Tile square(int level, uint64_t ix, uint64_t iy, int ru, int rv) {
  Tile tile;
  tile.level = level, tile.ix = ix, tile.iy = iy;
  tile.ru = ru, tile.rv = rv;
  return tile;
}

// A root cut into quadrants: A (0, 0) one cell; B (1, 0) a strip of two cells along v; the top
// left quadrant four one-cell tiles of level 2; D (1, 1) one cell.
std::vector<Tile> quadrants() {
  return {square(1, 0, 0, 1, 1), square(1, 1, 0, 1, 2), square(2, 0, 2, 1, 1), square(2, 1, 2, 1, 1),
          square(2, 0, 3, 1, 1), square(2, 1, 3, 1, 1), square(1, 1, 1, 1, 1)};
}

TEST(RootTileIndex, FindsTheTileCoveringASquare) {
  const std::vector<Tile> tiles = quadrants();
  RootTileIndex index;
  index.index(tiles);
  EXPECT_EQ(index.covering(1, 0, 0), 0u);
  EXPECT_EQ(index.covering(3, 7, 1), 1u);  // deep inside B
  EXPECT_EQ(index.covering(2, 1, 3), 5u);
  EXPECT_EQ(index.covering(1, 0, 1), UINT32_MAX);  // four smaller tiles cover it
}

TEST(RootTileIndex, InnerSidesGetPointsFromSmallerTilesAndShorterCells) {
  const std::vector<Tile> tiles = quadrants();
  RootTileIndex index;
  index.index(tiles);
  // A's right side meets B's left side, two cells of half its length: B's middle point is on it.
  EXPECT_TRUE(index.innerSideGetsPoints(tiles, 0, 1));
  // A's top side meets two level-2 tiles: their shared corner is on it.
  EXPECT_TRUE(index.innerSideGetsPoints(tiles, 0, 2));
  // B's top side meets D's bottom side, one cell each: only the corners.
  EXPECT_FALSE(index.innerSideGetsPoints(tiles, 1, 2));
  EXPECT_FALSE(index.innerSideGetsPoints(tiles, 6, 0));
  // A level-2 tile's right side meets D's left side, longer than it: nothing inside it.
  EXPECT_FALSE(index.innerSideGetsPoints(tiles, 3, 1));
  // D's left side meets two level-2 tiles: their shared corner.
  EXPECT_TRUE(index.innerSideGetsPoints(tiles, 6, 3));
}

// Planning checks pending tiles against the tiles of their own root (Planner::settleInnerSides):
// none that those sides break is left for the rounds, judged by TileNeighbors over the whole plan.
TEST(RootTileIndex, PlanningLeavesNoPendingTileItsOwnRootBreaks) {
  for (const char* name : {"opensubdiv-shapes/catmark_torus_creases0", "bigguy", "car"}) {
    SCOPED_TRACE(name);
    const ControlMesh mesh = readObjFile(testing::modelsDir() + "/" + name + ".obj");
    const PatchSet set = buildPatchSet(mesh);
    TessellationOptions options;
    options.accuracy = Accuracy::relative(1e-3);
    RootTiles tiles;
    planRoots(set.adaptive->tree, set, options, tiles);
    const TileNeighbors neighbors(set.adaptive->rootSeams, tiles);
    size_t pending = 0, brokenOnInnerSides = 0;
    for (uint32_t r = 0; r < tiles.size(); ++r) {
      for (uint32_t t = 0; t < tiles[r].size(); ++t) {
        const Tile& tile = tiles[r][t];
        if (!tile.pendingPair) continue;
        ++pending;
        uint8_t sides = 0;
        for (int k = 0; k < 4; ++k) {
          if (!tile.onRootSide(k) && neighbors.sideGetsPoints(r, t, k)) sides |= uint8_t(1 << k);
        }
        brokenOnInnerSides += tile.boundWithPoints(sides) > tile.tolerance;
      }
    }
    EXPECT_GT(pending, 0u);
    EXPECT_EQ(brokenOnInnerSides, 0u);
  }
}

}  // namespace
}  // namespace tessera
