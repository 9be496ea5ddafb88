// The adaptive user path (docs/ADAPTIVE.md): plan tiles over the surface tree, stitch their seams,
// evaluate every vertex once on the exact limit surface, triangulate the tiles. The mesh is
// watertight (shared points are one vertex; across creases one position, a normal per side) and
// within the plan's proven bound of the limit surface.
#pragma once

#include <functional>

#include "core/adaptive/adaptive_plan.h"
#include "core/mesh/triangle_mesh.h"
#include "core/stitching/tile_stitching.h"
#include "core/stitching/vertex_evaluation.h"
#include "core/surface/adaptive_surface.h"

namespace tessera {

// Tiles and their seams, every bound settled.
struct AdaptiveLayout {
  AdaptivePlan plan;
  Stitching stitching;
  int rounds = 0;  // plans it took (docs/ADAPTIVE.md §5: one-cell tiles checked after stitching)
};

// Plans and stitches; a one-cell tile planned on its corners' bound alone that got points on a
// side whose bow breaks its ε is planned again without that shortcut, until none does.
AdaptiveLayout layoutAdaptive(const PatchSet& patches, const AdaptiveSurface& surface,
                              const TessellationOptions& options);

// With recordParameters (tests, tools; a GLB needs none of it): trianglePiece holds each
// triangle's tile, vertexFace/vertexSubFace/vertexUv where each vertex was evaluated, vertexPoint
// the vertex each copy repeats, and each triangle's root and its corners' (u, v) there.
// `evaluation` (may be null: the CPU's, fused with triangulation) puts the vertices on the surface.
TriangleMesh tessellateAdaptive(const PatchSet& patches, const AdaptiveSurface& surface, const AdaptiveLayout& layout,
                                bool recordParameters = false, const std::function<void()>& checkpoint = {},
                                VertexEvaluation* evaluation = nullptr);

}  // namespace tessera
