// UVs for a tessellated mesh: each triangle corner's UV evaluated on the limit surface in its own
// base face, and a vertex split where the faces around it disagree (a UV seam), so positions
// stay bit-identical on both sides and the mesh stays watertight by position.
#pragma once

#include <functional>

#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/mesh/triangle_mesh.h"
#include "core/topology/limit_uvs.h"

namespace tessera {

// `corners`: where each triangle corner lies (base face, sub-face, (u, v) in Bfr's
// parameterization). Fills `mesh.uvs` (u, v per vertex) and appends the seam copies of vertices
// (position, normal and any per-vertex records repeated; vertexPoint names the vertex copied).
// `checkpoint` (may be empty) is called between its passes and every 64K corners, and may throw
// to abandon the work.
void attachUvs(const ControlMesh& control, const LimitUvs& uvs, const std::vector<UvQuery>& corners, TriangleMesh& mesh,
               const std::function<void()>& checkpoint = {});

}  // namespace tessera
