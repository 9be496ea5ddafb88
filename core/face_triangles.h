// Triangular base faces as one triangle (docs/ADAPTIVE.md §6a). Catmull-Clark parameterizes a
// triangle as three quad sub-faces, so planned root by root a triangle costs at least three
// one-cell tiles (six triangles) and puts the middles of its edges on its neighbours' sides, where
// OpenSubdiv's uniform rate 1 makes one triangle. When each sub-face became one one-cell tile and
// the face's bound allows, the three tiles become one triangle through the face's limit corners;
// it holds once stitched if no neighbour put a point on its edges, and is refused otherwise.
#pragma once

#include <cstdint>
#include <vector>

#include "core/adaptive_plan.h"
#include "core/adaptive_surface.h"
#include "core/patch_set.h"
#include "core/tile_stitching.h"

namespace tessera {

// Marks (Tile::faceTriangle) the tiles of every triangular face not `refused` (per base face)
// whose sub-faces are each one one-cell tile and whose triangle's bound is within their ε, and
// gives those tiles the triangle's bound. Tile t of sub-face 0 has sub-faces 1 and 2 at t + 1, t + 2.
void joinFaceTriangles(AdaptivePlan& plan, const PatchSet& patches, const AdaptiveSurface& surface,
                       const std::vector<uint8_t>& refused);

// Whether every face triangle's edges, as stitched, hold its corners alone; faces whose edges got
// more points are marked in `refused` (their sub-faces' tiles serve them next time).
bool faceTrianglesHold(const AdaptivePlan& plan, const Stitching& stitching, const SurfaceTree& tree,
                       std::vector<uint8_t>& refused);

}  // namespace tessera
