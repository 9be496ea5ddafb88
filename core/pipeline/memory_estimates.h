// What core's work takes in memory, estimated before it is done, so that a server can budget a
// job before running it (server/calls/admission_control.h). Each figure is a fit to the peak resident
// memory measured on ../shared/models (bench/MEMORY-RESULTS.md) with room above every model
// measured; none is a proven bound.
#pragma once

#include <cstdint>

#include "core/mesh/control_mesh.h"

namespace tessera {

// OpenSubdiv Far's adaptive refinement and patch table for a mesh whose refinement makes
// `refinedVertices` vertices (core/topology/refinement_budget.h estimates them before refining).
int64_t refinementBytes(int64_t refinedVertices);

// The whole of buildPatchSet, peak, once the refinement's vertex count is known: the refinement,
// the patches and rings, and the surface tree, whose extraordinary-vertex chains grow with the
// valences around the mesh's irregular vertices and non-quad faces.
int64_t preprocessingBytes(const ControlMesh& mesh, int64_t refinedVertices);

// tessellate() and writeGlb() for an output of `triangles` triangles, peak: the plan and seams,
// the mesh with its per-vertex records, and the GLB; `uvs`: with the mesh's UVs (the triangles'
// parameters, each vertex's UV and the seam copies).
int64_t tessellationBytes(int64_t triangles, bool uvs = false);

}  // namespace tessera
