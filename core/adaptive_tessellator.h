// The adaptive user path (docs/ADAPTIVE.md): plan tiles over the surface tree, stitch their seams,
// evaluate every vertex once on the exact limit surface, triangulate the tiles. The mesh is
// watertight (shared points are one vertex; across creases one position, a normal per side) and
// within the plan's proven bound of the limit surface.
#pragma once

#include <functional>

#include "core/adaptive_plan.h"
#include "core/adaptive_surface.h"
#include "core/watertight_tessellator.h"

namespace tessera {

// trianglePiece holds each triangle's tile; vertexFace/vertexSubFace/vertexUv where each vertex
// was evaluated; with recordParameters, each triangle's root and its corners' (u, v) there.
TriangleMesh tessellateAdaptive(const PatchSet& patches, const AdaptiveSurface& surface, const AdaptivePlan& plan,
                                bool recordParameters = false, const std::function<void()>& checkpoint = {});

}  // namespace tessera
