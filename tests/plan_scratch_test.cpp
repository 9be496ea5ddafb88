// Planning's room kept from call to call (core/adaptive/plan_scratch.h), and which one-cell tiles planning
// leaves pending (kPendingSaving, docs/ADAPTIVE.md §3).
#include "core/adaptive/plan_scratch.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

struct Model {
  ControlMesh mesh;
  PatchSet set;
  explicit Model(const std::string& name)
      : mesh(readObjFile(testing::modelsDir() + "/" + name + ".obj")), set(buildPatchSet(mesh)) {}
};

TessellationOptions relative(double epsilon) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(epsilon);
  return options;
}

void expectSameTiles(const RootTiles& a, const RootTiles& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t r = 0; r < a.size(); ++r) {
    ASSERT_EQ(a[r].size(), b[r].size()) << "root " << r;
    for (size_t t = 0; t < a[r].size(); ++t) {
      const Tile &x = a[r][t], &y = b[r][t];
      EXPECT_TRUE(x.level == y.level && x.ix == y.ix && x.iy == y.iy && x.ru == y.ru && x.rv == y.rv &&
                  x.bound == y.bound && x.pendingPair == y.pendingPair && x.spanU == y.spanU && x.spanV == y.spanV)
          << "root " << r << " tile " << t;
    }
  }
}

// Room left by another mesh (other roots, other tiles, indexed) plans a mesh with holes (roots
// without tiles) as fresh vectors do, tile for tile, and its indexes answer alike: emptied by the
// pool (clearKeepingRoom) or not, a hole's index must not keep the other mesh's entries.
TEST(PlanScratch, RoomKeptFromAnotherMeshPlansAsFreshRoomDoes) {
  const Model torus("opensubdiv-shapes/catmark_torus_creases0"), holes("opensubdiv-shapes/catmark_hole_test1");
  const SurfaceTree& tree = holes.set.adaptive->tree;
  RootTiles fresh;
  std::vector<RootTileIndex> freshIndexes;
  planRoots(tree, holes.set, relative(1e-3), fresh, &freshIndexes);
  for (const bool emptied : {true, false}) {
    SCOPED_TRACE(emptied ? "emptied" : "as left");
    PlanScratch kept;
    planRoots(torus.set.adaptive->tree, torus.set, relative(1e-3), kept.tiles, &kept.indexes);
    size_t keptHoles = 0;  // holes whose room the torus used
    for (size_t r = 0; r < tree.roots.size(); ++r) {
      keptHoles += tree.roots[r].node == kNoNode && r < kept.tiles.size() && !kept.tiles[r].empty();
    }
    ASSERT_GT(keptHoles, 0u);
    if (emptied) {
      EXPECT_GT(kept.clearKeepingRoom(), 0u);
    }

    planRoots(tree, holes.set, relative(1e-3), kept.tiles, &kept.indexes);
    expectSameTiles(kept.tiles, fresh);
    // Every square of levels 0..3 of every root, through both indexes.
    for (size_t r = 0; r < tree.roots.size(); ++r) {
      for (int level = 0; level <= 3; ++level) {
        for (uint64_t iy = 0; iy < (uint64_t(1) << level); ++iy) {
          for (uint64_t ix = 0; ix < (uint64_t(1) << level); ++ix) {
            EXPECT_EQ(kept.indexes[r].covering(level, ix, iy), freshIndexes[r].covering(level, ix, iy))
                << "root " << r << " square " << level << " " << ix << " " << iy;
          }
        }
      }
    }
  }
}

// A one-cell tile is left pending only where the pair through its corners holds and points on a
// side could break it, and, below its root's own square, where its settled grid needs more than
// kPendingSaving + 1 triangles; a settled grid it carries (for a failure to take in place) holds
// its ε.
TEST(PlanScratch, PendingTilesSaveEnoughOverTheirSettledGrids) {
  for (const char* name : {"bigguy", "car"}) {
    SCOPED_TRACE(name);
    const Model model(name);
    RootTiles tiles;
    planRoots(model.set.adaptive->tree, model.set, relative(1e-3), tiles);
    size_t pending = 0, carried = 0;
    for (const std::vector<Tile>& root : tiles) {
      for (const Tile& tile : root) {
        if (!tile.pendingPair || tile.cellwise) continue;
        ++pending;
        EXPECT_LE(tile.bound, tile.tolerance);
        EXPECT_GT(tile.boundWithPoints(15), tile.tolerance);
        if (tile.settledRu == 0) continue;
        ++carried;
        if (tile.level > 0) {
          EXPECT_GT(2 * tile.settledRu * tile.settledRv, 8);
        }
        EXPECT_LE(tile.settledBound, tile.tolerance);
      }
    }
    EXPECT_GT(pending, 0u);
    EXPECT_GT(carried, 0u);
  }
}

}  // namespace
}  // namespace tessera
