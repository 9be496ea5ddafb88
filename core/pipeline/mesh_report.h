// What Tessera sees in a mesh (`tessera inspect`): the control mesh's make-up and what
// preprocessing reduced it to. Plain data; the CLI formats it as text or JSON.
#pragma once

#include <map>
#include <string>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"

namespace tessera {

struct MeshReport {
  int vertices = 0, faces = 0, unusedVertices = 0;
  std::map<int, int> faceSizes;  // face size -> count
  std::map<int, int> valences;   // vertex valence (incident edges) -> count
  int edges = 0, boundaryEdges = 0;
  // Where OpenSubdiv's rules for non-manifold topology apply (core/mesh/manifold_sheets.h): edges as
  // the input's vertex pairs, vertices as the input's. Known once preprocessing accepted the mesh.
  int nonManifoldEdges = 0, nonManifoldVertices = 0;
  int creases = 0, infiniteCreases = 0, corners = 0, holes = 0;
  std::string boundaryInterpolation, creaseMethod, triangleSubdivision;
  // After preprocessing:
  int regularPatches = 0;
  std::map<std::string, std::map<int, int>> ringsByKind;  // kind -> valence -> count
  int locallyRefinedFaces = 0, isolationLevel = 0;
  std::string refusal;  // non-empty when preprocessing refused the mesh (the error message)
};

// Describes the control mesh, then preprocesses it; a refusal is recorded, not thrown.
MeshReport inspectMesh(const ControlMesh& mesh);

// "interior", "boundary", "crease" or "corner": how the FAS rules treat a ring's EV.
std::string ringKind(const RingSet& rings, size_t r);

}  // namespace tessera
