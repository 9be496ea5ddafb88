// How far a triangle mesh lies from Far's uniform refinement of its cage: the refined control mesh
// (its faces fanned into triangles) converges to the limit surface as the level grows, so the
// distance at two levels measures the mesh against the limit with neither Bfr nor a projection
// (tessera-limit-check --far-level, the semi-sharp corner test).
#pragma once

#include "core/mesh/control_mesh.h"
#include "reference/limit_distance.h"

namespace tessera::testing {

// The largest distance from `mesh` (its vertices and seven points of each triangle: the centroid,
// the edge midpoints and the points halfway between the centroid and the corners) to the nearest
// triangle of Far's uniform refinement of `cage` at `level`.
double distanceToFarRefinement(const ControlMesh& cage, int level, const TriangleMeshView& mesh);

}  // namespace tessera::testing
