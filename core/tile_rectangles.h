// Dyadic rectangle tiles (docs/ADAPTIVE.md §6b): a root's settled cell-type tiles (one-cell
// tiles, one-cell-wide strips, cell-wise tiles) of one size, rates and diagonal that lie side by
// side as the two halves of an aligned rectangle become one cell-wise tile over it, again and
// again. Every side of a cell-type tile keeps its own grid points (a strip's short side and a
// one-cell side have only their corners as grid points), so the lines get the same points, every
// cell the same polygon and the same triangles, and every bound still holds: only the per-tile
// work of the later phases (stitching, the neighbour rounds, triangulation) shrinks.
#pragma once

#include <vector>

#include "core/adaptive_plan.h"
#include "core/surface_tree.h"

namespace tessera {

// Merges the tiles of one root (`top`: its tree node at level 0) in place, in tree order; pending
// tiles, face triangles and tiles whose cells keep different diagonals are left as they are.
// Planning calls it once a root is planned and again each time squares of it are planned again
// (their pending tiles settled).
void mergeRectangles(const SurfaceTree& tree, const NodeSquare& top, std::vector<Tile>& tiles);

}  // namespace tessera
