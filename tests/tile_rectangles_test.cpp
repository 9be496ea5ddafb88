// Dyadic rectangle tiles (core/adaptive/tile_rectangles.h, docs/ADAPTIVE.md §6b).
#include "core/adaptive/tile_rectangles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/stitching/adaptive_tessellator.h"
#include "core/surface/adaptive_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

// A settled tile of `root`'s square (level, ix, iy); its node is the root's (level 0), which
// holds every rectangle, so merging never walks the (empty) tree.
Tile square(int level, uint64_t ix, uint64_t iy, int ru, int rv, float bound = 1,
            bool cellwise = false) {
  Tile tile;
  tile.node = {0, 0, 0, 0};
  tile.level = level, tile.ix = ix, tile.iy = iy;
  tile.ru = ru, tile.rv = rv;
  tile.bound = bound, tile.tolerance = 2;
  tile.cellwise = cellwise;
  return tile;
}

TEST(TileRectangles, AColumnOfStripsBecomesOneCellwiseRectangle) {
  std::vector<Tile> tiles;
  for (uint64_t iy = 0; iy < 8; ++iy)
    tiles.push_back(square(3, 2, iy, 5, 1, 0.25f + 0.1f * float(iy)));
  mergeRectangles(SurfaceTree(), {0, 0, 0, 0}, tiles);
  ASSERT_EQ(tiles.size(), 1u);
  const Tile& t = tiles[0];
  EXPECT_EQ(std::tie(t.level, t.ix, t.iy, t.spanU, t.spanV),
            std::make_tuple(3, uint64_t(2), uint64_t(0), uint8_t(0), uint8_t(3)));
  EXPECT_EQ(t.ru, 5);
  EXPECT_EQ(t.rv, 8);
  EXPECT_TRUE(t.cellwise);  // its cells triangulated one by one, as the strips' were
  EXPECT_FLOAT_EQ(t.bound, 0.95f);
  EXPECT_EQ(t.width(), 0.125);
  EXPECT_EQ(t.height(), 1.0);
  // Every line keeps each cell's corners, as the strips' long sides and one-cell ends did.
  EXPECT_EQ(t.keptIntervals(0), 5);
  EXPECT_EQ(t.keptIntervals(1), 8);
}

TEST(TileRectangles, GridTilesMergeKeepingTheirSquaresCorners) {
  std::vector<Tile> tiles = {square(2, 0, 1, 3, 4), square(2, 1, 1, 3, 4), square(2, 0, 0, 3, 4),
                             square(2, 1, 0, 3, 4)};
  mergeRectangles(SurfaceTree(), {0, 0, 0, 0}, tiles);
  ASSERT_EQ(tiles.size(), 1u);
  const Tile& t = tiles[0];
  EXPECT_EQ(std::tie(t.ix, t.iy, t.spanU, t.spanV),
            std::make_tuple(uint64_t(0), uint64_t(0), uint8_t(1), uint8_t(1)));
  EXPECT_EQ(t.ru, 6);
  EXPECT_EQ(t.rv, 8);
  EXPECT_FALSE(t.cellwise);
  // Sides keep the corners of the squares they were made of: halves.
  for (int k = 0; k < 4; ++k) EXPECT_EQ(t.keptIntervals(k), 2) << k;
  EXPECT_EQ(t.levelAlong(0), 1);
  EXPECT_EQ(t.indexAlong(1), 0u);
  EXPECT_TRUE(t.onRootSide(0) && t.onRootSide(3));
  EXPECT_FALSE(t.onRootSide(1) || t.onRootSide(2));
}

TEST(TileRectangles, OnlyAlignedSettledTilesOfOneKindAndRateMerge) {
  const std::vector<Tile> apart = {
      square(2, 1, 0, 3, 3), square(2, 2, 0, 3, 3),  // not the halves of an aligned rectangle
      square(2, 0, 1, 3, 3), square(2, 1, 1, 3, 2),  // different rates
      square(2, 0, 2, 2, 2), square(2, 1, 2, 2, 2, 1, true),  // a grid beside a cell-wise tile
      square(3, 0, 6, 1, 1), square(2, 1, 3, 1, 1),           // different sizes
  };
  std::vector<Tile> tiles = apart;
  mergeRectangles(SurfaceTree(), {0, 0, 0, 0}, tiles);
  EXPECT_EQ(tiles.size(), apart.size());
  std::vector<Tile> pending = {square(2, 0, 0, 1, 1), square(2, 1, 0, 1, 1)};
  pending[1].pendingPair = true;  // its bound waits for its sides' points
  mergeRectangles(SurfaceTree(), {0, 0, 0, 0}, pending);
  EXPECT_EQ(pending.size(), 2u);
  std::vector<Tile> wide(2, square(1, 0, 0, 40, 2));  // 80 cells would pass kMaxTileRate
  wide[1].ix = 1;
  mergeRectangles(SurfaceTree(), {0, 0, 0, 0}, wide);
  EXPECT_EQ(wide.size(), 2u);
}

// The plan split back into squares, each the part of its rectangle it was (a cell-wise part
// keeps its cells; a grid part its rates).
AdaptivePlan squaresOf(const AdaptivePlan& plan) {
  AdaptivePlan split = plan;
  split.tiles.clear();
  split.rootFirstTile.assign(1, 0);
  for (size_t r = 0; r + 1 < plan.rootFirstTile.size(); ++r) {
    for (uint32_t t = plan.rootFirstTile[r]; t < plan.rootFirstTile[r + 1]; ++t) {
      const Tile& tile = plan.tiles[t];
      for (uint64_t iy = tile.iy; iy < tile.iyEnd(); ++iy) {
        for (uint64_t ix = tile.ix; ix < tile.ixEnd(); ++ix) {
          Tile part = tile;
          part.ix = ix, part.iy = iy, part.spanU = part.spanV = 0;
          part.ru = tile.ru >> tile.spanU, part.rv = tile.rv >> tile.spanV;
          split.tiles.push_back(part);
        }
      }
    }
    split.rootFirstTile.push_back(uint32_t(split.tiles.size()));
  }
  return split;
}

// Whether every vertex of `a` has one of `b` within `tolerance` (the same points computed two
// ways round differently).
bool everyVertexIn(const TriangleMesh& a, const TriangleMesh& b, double tolerance) {
  std::vector<Vec3> sorted = b.positions;
  std::sort(sorted.begin(), sorted.end(), [](const Vec3& p, const Vec3& q) { return p.x < q.x; });
  for (const Vec3& p : a.positions) {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), p.x - tolerance,
                               [](const Vec3& q, double x) { return q.x < x; });
    bool found = false;
    for (; it != sorted.end() && it->x <= p.x + tolerance && !found; ++it)
      found = length(*it - p) <= tolerance;
    if (!found) return false;
  }
  return true;
}

// Against the same plan's squares, stitched and triangulated each as a tile: a rectangle's
// lines get the same points (the same vertices, up to the rounding of the two ways of computing
// their parameters) and its region as many triangles; and every triangle of a
// rectangle lies in one of its squares, the squares whose bounds it keeps (docs/ADAPTIVE.md §6b).
TEST(TileRectangles, TheSameVerticesAsTheirSquaresAndEveryTriangleInOneSquare) {
  for (const auto& [name, relative] :
       {std::pair<std::string, double>{"opensubdiv-shapes/catmark_torus_creases0", 1e-3},
        {"bigguy", 1e-3},
        {"car", 1e-3}}) {
    SCOPED_TRACE(name);
    const ControlMesh mesh = readObjFile(testing::modelsDir() + "/" + name + ".obj");
    const PatchSet set = buildPatchSet(mesh);
    TessellationOptions options;
    options.accuracy = Accuracy::relative(relative);
    const AdaptiveLayout merged = layoutAdaptive(set, *set.adaptive, options);
    AdaptiveLayout split;
    split.plan = squaresOf(merged.plan);
    split.stitching = stitchTiles(split.plan, set.adaptive->tree, set.adaptive->lines, {});
    const size_t rectangles = std::count_if(merged.plan.tiles.begin(), merged.plan.tiles.end(),
                                            [](const Tile& t) { return t.spanU || t.spanV; });
    const size_t grids =
        std::count_if(merged.plan.tiles.begin(), merged.plan.tiles.end(),
                      [](const Tile& t) { return (t.spanU || t.spanV) && !t.cellwise; });
    EXPECT_GT(rectangles, 20u);
    EXPECT_GT(grids, 10u);
    EXPECT_LT(merged.plan.tiles.size(), split.plan.tiles.size());
    const TriangleMesh a = tessellateAdaptive(set, *set.adaptive, merged, true);
    const TriangleMesh b = tessellateAdaptive(set, *set.adaptive, split, true);
    EXPECT_EQ(a.triangleCount(), b.triangleCount());
    EXPECT_EQ(a.positions.size(), b.positions.size());
    EXPECT_TRUE(everyVertexIn(a, b, 1e-5) && everyVertexIn(b, a, 1e-5));
    size_t checked = 0;
    for (size_t t = 0; t < a.triangleCount(); ++t) {
      const Tile& tile = merged.plan.tiles[a.trianglePiece[t]];
      if (!tile.spanU && !tile.spanV) continue;
      // In square units of the tile's level: all three corners in one closed unit square.
      const double size = std::ldexp(1.0, -tile.level);
      double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
      for (int k = 0; k < 3; ++k) {
        for (int d = 0; d < 2; ++d) {
          const double x = a.triangleST[6 * t + 2 * k + d] / size;
          lo[d] = std::min(lo[d], x), hi[d] = std::max(hi[d], x);
        }
      }
      for (int d = 0; d < 2; ++d) {
        ASSERT_LE(std::ceil(lo[d] - 1e-9), std::floor(hi[d] + 1e-9) + 1) << "triangle " << t;
        ASSERT_LE(hi[d] - std::floor(lo[d] + 1e-9), 1 + 1e-9)
            << "triangle " << t << " crosses a square's side";
      }
      ++checked;
    }
    EXPECT_GT(checked, 100u);
  }
}

}  // namespace
}  // namespace tessera
