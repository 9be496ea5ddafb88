// A bound on OpenSubdiv's adaptive refinement before it is made. Semi-sharp creases are isolated
// level by level until their sharpness decays, and the refined region can double or more per
// level: a 150 KB mesh whose 2,900 edges all have sharpness 9.5 refines to ~40 million vertices,
// ~20 GB once the patch set is built from it (~650 bytes per refined vertex, measured). So a
// request for such a mesh is refused from a few cheap partial refinements instead.
#pragma once

#include <cstdint>
#include <functional>

#include "core/mesh/control_mesh.h"

namespace tessera {

// Refinements to 1, 2, ... levels (each a fraction of the next) give the vertex count per level;
// the levels still to come are extrapolated at the last level's growth while semi-sharp features
// still refine, without growth after (growth falls as creases' sharpness runs out, so this
// overestimates). Returns once an estimate (or the complete count) is
// within the limit; throws TesseraError (limit) naming the estimate and the limit when it is
// hopelessly over (8 times), or when the next partial refinement would itself take twice the
// limit. `checkpoint` (may be empty) runs between them. Returns the estimate (the exact count
// where the refinement was complete), which callers use to budget memory before refining.
int64_t requireRefinementWithin(const ControlMesh& mesh, int64_t maxRefinedVertices,
                             const std::function<void()>& checkpoint);

}  // namespace tessera
