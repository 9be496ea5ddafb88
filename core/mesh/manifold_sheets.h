// Non-manifold control meshes as manifold sheets (docs/NONMANIFOLD.md). OpenSubdiv makes every
// non-manifold edge (shared by three or more faces, by two faces running the same way, by one
// face twice, or from a vertex to itself) infinitely sharp, and every non-manifold vertex (its
// faces form several fans, or it touches a non-manifold edge) an infinitely sharp corner, except
// a vertex inside an interior non-manifold crease, which keeps the crease rule (Far's
// TopologyRefinerFactoryBase::prepareComponentTagsAndSharpness). No refinement rule then reads
// across a non-manifold edge or vertex except the crease and corner rules, which read only
// points on it. So cutting the mesh there — one copy of each such vertex per fan of faces
// around it, each fan's copy carrying the sharpness OpenSubdiv gave the vertex — leaves every
// refined point where it was: the sheets' limit surface is the input's, face by face.
#pragma once

#include <utility>
#include <vector>

#include "core/mesh/control_mesh.h"

namespace tessera {

// Everything but the counts is empty unless cut(): a manifold input is its own sheets and seams.
struct ManifoldSheets {
  // The input cut into oriented 2-manifolds with boundary: the same faces in the same order,
  // with the same parameterization; vertices [0, V) are the input's, copies follow.
  ControlMesh sheets;
  std::vector<int> inputVertex;  // per sheet vertex, the input vertex it copies
  // The input with the sharpness OpenSubdiv implies made explicit (infinitely sharp creases on
  // its non-manifold edges, corners on the non-manifold vertices it sharpens), for the seams
  // between faces, which are the input's. Not for OpenSubdiv: a crease may run from a vertex
  // to itself.
  ControlMesh seams;
  int nonManifoldEdges = 0, nonManifoldVertices = 0;

  bool cut() const { return nonManifoldEdges > 0 || nonManifoldVertices > 0; }
  const ControlMesh& sheetsOf(const ControlMesh& input) const { return cut() ? sheets : input; }
  const ControlMesh& seamsOf(const ControlMesh& input) const { return cut() ? seams : input; }
};

// Expects a mesh that passed validateControlMesh() (one whose face indices are out of range is
// refused as kInvalidInput). Throws kUnsupported for a non-manifold mesh whose boundary rule is
// "none" (OpenSubdiv turns faces at a boundary into holes, and cutting makes boundaries). Time
// O(N log N) in the number of face vertices (one sort of the edges per vertex), memory O(N).
ManifoldSheets cutIntoSheets(const ControlMesh& mesh);

}  // namespace tessera
