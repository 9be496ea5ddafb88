// Refuses control meshes whose faces do not form an oriented 2-manifold (with boundary), the
// topology Tessera's patch construction assumes. OpenSubdiv accepts more (non-manifold edges and
// vertices, see its catmark_nonman_* shapes); Tessera does not, and says where the problem is.
#pragma once

#include "core/control_mesh.h"

namespace tessera {

// Throws TesseraError kUnsupported, naming the vertices and faces involved, when
//  - an edge is shared by more than two faces (a non-manifold edge),
//  - two faces traverse a shared edge in the same direction (inconsistent orientation), or
//  - the faces around a vertex form more than one fan (a "bow-tie" vertex).
// Vertices used by no face are fine. Expects a mesh that passed validateControlMesh(); one whose
// face indices are out of range is refused as kInvalidInput. Time O(N log N) in the number of
// face vertices (one sort of the edges), memory O(N).
void requireManifold(const ControlMesh& mesh);

}  // namespace tessera
