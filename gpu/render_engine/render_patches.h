// From a tessellation plan's Bézier pieces to the renderer's patches (paper §6: the pieces are
// drawn with their own levels, cracks between pieces are left to image-space crack filling,
// §6.2.3-6.2.4). Every edge of a piece gets the piece's FMM86 level N (MATH.md §4). The renderer
// caps levels at kMaxTessellationLevel (64, as D3D11), so a piece with N > 64 is halved k times
// in each direction by de Casteljau into 4^k sub-pieces of level ⌈N/2^k⌉: a finer grid than
// N×N in the piece's parameters, so the FMM86 bound still holds. Siblings share boundary
// control points bit for bit (both sides of a split copy the same midpoint), and the renderer
// evaluates a shared edge from those points alone, so sub-pieces of one piece join without
// cracks; only the outer edges of a piece can disagree with its neighbours.
#pragma once

#include <cstdint>
#include <vector>

#include "core/request/tessellation_options.h"
#include "core/uniform/tessellation_plan.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

// The smallest k with ⌈level / 2^k⌉ ≤ kMaxTessellationLevel (0 for levels that fit).
int splitCount(int level);

// Triangles the renderer draws for a piece of this level once split: 4^k sub-pieces with all
// edges at L = ⌈level / 2^k⌉, each 2L² triangles (tess_pattern.glsl with equal edge levels).
int64_t renderedTriangles(int level);

// Appends the piece's 4^k render patches (k = splitCount(piece.level)), all with `patchId`,
// row-major in (s, t) sub-squares: sub-patch (i, j) covers [i, i+1]/2^k × [j, j+1]/2^k.
void appendRenderPatches(const BezierPiece& piece, uint32_t patchId, std::vector<RenderPatch>& out);

// The part of space a camera can see, for discarding pieces on the CPU before they are split:
// a piece goes only when all its control points (hence its surface, by the convex hull
// property) lie outside one side plane of the view frustum or behind the eye. The side planes
// are widened by 1%, like the renderer's own culling guard band; there is no far plane (the
// renderer fits it to what it draws).
class ViewFrustum {
 public:
  // The camera must have passed validation (finite, eye ≠ target, up not parallel).
  explicit ViewFrustum(const tessera::Camera& camera);
  bool mayShow(const Vec3* points, int count) const;

 private:
  Vec3d eye_, right_, up_, forward_;
  double tanX_ = 0, tanY_ = 0;
};

}  // namespace tessera::gpu
