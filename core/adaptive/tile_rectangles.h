// Dyadic rectangle tiles (docs/ADAPTIVE.md §6b): a root's settled tiles of one size, rates, kind
// and diagonal that lie side by side as the two halves of an aligned rectangle become one tile
// over it, again and again, so that the per-tile work of the later phases (stitching, the
// neighbour rounds, triangulation) shrinks while every bound still holds:
// - cell-type tiles (one-cell tiles, strips, cell-wise tiles) become a cell-wise rectangle: every
//   side of theirs keeps its own grid points already (a strip's short side and a one-cell side
//   have only their corners as grid points), so the lines get the same points and every cell the
//   same polygon and triangles;
// - grid tiles become a grid rectangle whose sides keep the corners of its squares
//   (Tile::keptIntervals), so that no zip triangle crosses from one square into another.
#pragma once

#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/surface/surface_tree.h"

namespace tessera {

// Merges the tiles of one root (`top`: its tree node at level 0) in place, in tree order; pending
// tiles, face triangles and tiles whose cells keep different diagonals are left as they are.
// Planning calls it once a root is planned and again each time squares of it are planned again
// (their pending tiles settled).
void mergeRectangles(const SurfaceTree& tree, const NodeSquare& top, std::vector<Tile>& tiles);

}  // namespace tessera
