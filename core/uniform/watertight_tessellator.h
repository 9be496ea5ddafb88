// Watertight triangulation of a tessellation plan (MATH.md §5; the paper leaves it to future
// work). Every piece edge is split where its neighbours' edges end (FAS and Far level changes
// give T-junctions), each elementary interval gets one level (the finest its pieces ask for)
// and its vertices are computed once and shared, so every shared edge has bit-identical
// vertices. Each piece's N×N interior grid is stitched to its boundary polylines.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh/triangle_mesh.h"
#include "core/uniform/domain_keys.h"
#include "core/uniform/tessellation_plan.h"

namespace tessera {

// Triangle count the plan will produce, before building anything (for budgets).
int64_t estimateTriangles(const TessellationPlan& plan);

TriangleMesh tessellatePlan(const TessellationPlan& plan, const FaceTopology& faces,
                           bool recordParameters = false,
                           const std::function<void()>& checkpoint = {});

}  // namespace tessera
