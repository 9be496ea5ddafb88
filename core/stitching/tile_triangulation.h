// Triangles of one tile (docs/ADAPTIVE.md §5), counter-clockwise in (u, v). A tile of ru × rv
// cells with ru, rv ≥ 2 has an inner grid; each side's points are joined to the grid's border
// row by an anchored zip: one side point anchors each row interval, the side's segments between
// two anchors fan to the row point between them. Since no side has a gap wider than its own cell
// (tile_stitching.h), every triangle then fits in one cell's box. A one-cell tile, and each cell
// of a one-cell-wide strip, is a polygon of side points triangulated without inner points.
#pragma once

#include <cstdint>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/stitching/tile_stitching.h"

namespace tessera {

// Positions and normals of the vertices triangles are made of.
struct TriangulationVertices {
  const std::vector<Vec3>& positions;
  const std::vector<Vec3>& normals;

  const Vec3& position(uint32_t v) const { return positions[v]; }
  const Vec3& normal(uint32_t v) const { return normals[v]; }
};

// Triangles as vertex triples, and the corners (positions in `indices`) whose vertex normal the
// triangle's face normal points against, which is how a fold shows (adaptive_tessellator.cpp):
// found while the triangles are made, where quads have the test already.
struct TileTriangleOutput {
  std::vector<uint32_t> indices;
  std::vector<uint32_t> awayCorners;
};

// Appends tile t's triangles to `output`, for the tile's rates and inner grid vertices from
// `gridFirst` on (row by row); positions and normals choose quads' diagonals.
void triangulateTile(const Stitching& stitching, size_t t, const Tile& tile, uint32_t gridFirst,
                     const TriangulationVertices& vertices, TileTriangleOutput& output);

}  // namespace tessera
