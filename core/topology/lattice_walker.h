// Walks the regular quad lattice around a vertex of one Far refinement level, so that the
// vertices of an extraordinary ring can be gathered in CER order (cer_layout.h) straight from
// OpenSubdiv's topology. Used by preprocessing (ring extraction) and by the tests that compare
// FAS with Far's own refinement.
#pragma once

#include <optional>
#include <vector>

#include <opensubdiv/far/topologyLevel.h>

namespace tessera {

namespace Far = OpenSubdiv::Far;
using Far::Index;

// The faces around a vertex in sector order: sector i's face has the vertex at local corner
// rotation[i], its x-axis spoke toward faceVertices[(rotation+1)%4] and sector i+1 lies across
// its edge toward faceVertices[(rotation+3)%4].
struct VertexSectors {
  Index vertex = -1;
  std::vector<Index> faces;
  std::vector<int> rotation;
  bool open = false;  // the vertex is on a boundary: sector 0 and the last sector end at it
};

class LatticeWalker {
 public:
  explicit LatticeWalker(const Far::TopologyLevel& level) : level_(level) {}

  // Sector order around `vertex`; the first sector starts at the spoke toward `firstSpoke` when
  // given, at the boundary when the vertex is on one. nullopt when the faces around the vertex
  // are not all quads or do not form a single fan.
  std::optional<VertexSectors> sectorsAround(Index vertex, Index firstSpoke = -1) const;

  // Vertex at lattice point (x, y) >= 0 of sector i; -1 if the walk leaves quads or the mesh.
  Index latticeVertex(const VertexSectors& sectors, int sector, int x, int y) const;

  // Vertices in CER order: the ring (radius 2, 6n+1 points) or the refined set (radius 3,
  // 12n+1 points); -1 entries where the lattice is incomplete.
  std::vector<Index> gather(const VertexSectors& sectors, int radius) const;

  const Far::TopologyLevel& level() const { return level_; }

 private:
  struct Cell {
    Index face;
    int rotation;
  };
  std::optional<Cell> step(Cell cell, bool alongX) const;
  Index otherFace(Index edge, Index face) const;
  int localIndex(Index face, Index vertex) const;

  const Far::TopologyLevel& level_;
};

}  // namespace tessera
