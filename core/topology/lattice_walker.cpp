#include "core/topology/lattice_walker.h"

#include "core/rings/cer_layout.h"

namespace tessera {

Index LatticeWalker::otherFace(Index edge, Index face) const {
  auto faces = level_.GetEdgeFaces(edge);
  if (faces.size() != 2) return -1;
  return faces[0] == face ? faces[1] : faces[0];
}

int LatticeWalker::localIndex(Index face, Index vertex) const {
  auto vertices = level_.GetFaceVertices(face);
  for (int k = 0; k < vertices.size(); ++k) {
    if (vertices[k] == vertex) return k;
  }
  return -1;
}

// Crossing the cell's right edge (lattice (1,0)-(1,1)) or top edge ((1,1)-(0,1)): the new cell's
// origin is the old (1,0) or (0,1) corner, found by its local index in the neighbouring face.
std::optional<LatticeWalker::Cell> LatticeWalker::step(Cell cell, bool alongX) const {
  auto vertices = level_.GetFaceVertices(cell.face);
  auto edges = level_.GetFaceEdges(cell.face);
  int edgeCorner = alongX ? 1 : 2;
  Index next = otherFace(edges[(cell.rotation + edgeCorner) % 4], cell.face);
  if (next < 0 || level_.GetFaceVertices(next).size() != 4) return std::nullopt;
  Index newOrigin = vertices[(cell.rotation + (alongX ? 1 : 3)) % 4];
  int rotation = localIndex(next, newOrigin);
  if (rotation < 0) return std::nullopt;
  return Cell{next, rotation};
}

std::optional<VertexSectors> LatticeWalker::sectorsAround(Index vertex, Index firstSpoke) const {
  auto incident = level_.GetVertexFaces(vertex);
  for (Index face : incident) {
    if (level_.GetFaceVertices(face).size() != 4) return std::nullopt;
  }
  VertexSectors result;
  result.vertex = vertex;
  result.open = level_.IsVertexBoundary(vertex);
  Index start = -1;
  for (Index face : incident) {
    int k = localIndex(face, vertex);
    auto vertices = level_.GetFaceVertices(face);
    Index spoke = vertices[(k + 1) % 4];
    bool startsAtBoundary = otherFace(level_.GetFaceEdges(face)[k], face) < 0;
    if ((firstSpoke >= 0 && spoke == firstSpoke) || (firstSpoke < 0 && !result.open) ||
        (firstSpoke < 0 && result.open && startsAtBoundary)) {
      start = face;
      break;
    }
  }
  if (start < 0) return std::nullopt;
  Index face = start;
  do {
    int k = localIndex(face, vertex);
    result.faces.push_back(face);
    result.rotation.push_back(k);
    face = otherFace(level_.GetFaceEdges(face)[(k + 3) % 4], face);
  } while (face >= 0 && face != start && result.faces.size() <= size_t(incident.size()));
  if (result.faces.size() != size_t(incident.size()) || (face < 0) != result.open) {
    return std::nullopt;
  }
  return result;
}

Index LatticeWalker::latticeVertex(const VertexSectors& sectors, int sector, int x, int y) const {
  if (x == 0 && y == 0) return sectors.vertex;
  int cellX = x > 0 ? x - 1 : 0, cellY = y > 0 ? y - 1 : 0;
  std::optional<Cell> cell = Cell{sectors.faces[sector], sectors.rotation[sector]};
  for (int i = 0; i < cellX && cell; ++i) cell = step(*cell, true);
  for (int i = 0; i < cellY && cell; ++i) cell = step(*cell, false);
  if (!cell) return -1;
  // Lattice corners (0,0),(1,0),(1,1),(0,1) of the cell are local corners rotation + 0..3.
  int dx = x - cellX, dy = y - cellY;
  int corner = dy == 0 ? dx : 3 - dx;
  return level_.GetFaceVertices(cell->face)[(cell->rotation + corner) % 4];
}

std::vector<Index> LatticeWalker::gather(const VertexSectors& sectors, int radius) const {
  cer::RingShape shape{static_cast<int>(sectors.faces.size()), sectors.open};
  int count = radius == 2 ? shape.ringPointCount() : shape.refinedPointCount();
  std::vector<Index> result(count, -1);
  result[0] = sectors.vertex;
  for (int i = 0; i < shape.sectors; ++i) {
    for (int y = 0; y <= radius; ++y) {
      for (int x = 1; x <= radius; ++x) {
        result[cer::refinedIndexCanonical(shape, i, x, y)] = latticeVertex(sectors, i, x, y);
      }
    }
  }
  if (shape.open) {  // the closing spoke: lattice (0, x) of the last sector
    for (int x = 1; x <= radius; ++x) {
      result[cer::refinedIndexCanonical(shape, shape.sectors, x, 0)] =
          latticeVertex(sectors, shape.sectors - 1, 0, x);
    }
  }
  return result;
}

}  // namespace tessera
