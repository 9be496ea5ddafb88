// Watertight seams between tiles (docs/ADAPTIVE.md §5). Every tile side lies on a line of the
// domain (a base edge, an n-gon spoke, or a line inside a root); the sides on one line agree on
// one set of points there, each named once, so the two sides of every seam share bit-identical
// vertices. A line's points are its sides' corners, the own grid points of sides that must keep
// them (the long sides of one-cell-wide strips, every side of a cell-wise tile), and, densest side
// first, a side's own grid points wherever the points so far leave a gap wider than that side's
// cell: so no side ever sees a gap wider than its own cells, which is what keeps every triangle
// inside one cell's box.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/base/uninitialized_vector.h"
#include "core/surface/seam_lines.h"

namespace tessera {

// A vertex of the output and where to evaluate it: tile `tile`'s root at (u, v). A vertex that
// repeats another's position with its own normal (the other side of a crease) names that one in
// `positionOf`; otherwise positionOf is itself.
struct VertexRequest {
  uint32_t tile;
  double u, v;
  uint32_t positionOf;
};

// A point on a tile side: its vertex and its coordinate along the side in [0, 1], sides running
// along u (sides 0 and 2) or v (sides 1 and 3), increasing; `back` is 1 − at, each the double
// nearest the exact value, so that comparisons agree with the exact order from either end.
struct SidePoint {
  uint32_t vertex;
  double at, back;
  int qualifier;  // while stitching: which side of a crease the tile is on (-1: no split)
};

struct Stitching {
  UninitializedVector<VertexRequest> vertices;  // written in full by stitchTiles
  UninitializedVector<SidePoint> sidePoints;
  std::vector<uint32_t> sideFirst;  // side k of tile t: [sideFirst[4t + k], sideFirst[4t + k + 1])
  std::vector<uint32_t> gridFirst;  // tile t's (ru − 1)(rv − 1) inner grid vertices, row by row
  // Root r's own vertices (its tiles' inner corners, lines and grids), which only its tiles use:
  // [rootFirstVertex[r], rootFirstVertex[r + 1]); from the last entry on, the seam vertices (on
  // base edges and spokes, shared by tiles of several roots), and from copyFirst on the copies
  // that split a seam vertex's normal (positionOf names the original).
  std::vector<uint32_t> rootFirstVertex;
  uint32_t copyFirst = 0;

  const SidePoint* side(size_t tile, int k, size_t& count) const {
    count = sideFirst[4 * tile + k + 1] - sideFirst[4 * tile + k];
    return sidePoints.data() + sideFirst[4 * tile + k];
  }
};

// The root each tile belongs to is found from plan.rootFirstTile.
Stitching stitchTiles(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamLines& lines,
                      const std::function<void()>& checkpoint);

}  // namespace tessera
