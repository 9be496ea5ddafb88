#include "core/topology/ring_extraction.h"

#include <optional>
#include <string>
#include <utility>

#include "core/base/error.h"
#include "core/rings/fas.h"
#include "core/topology/lattice_walker.h"

namespace tessera {

namespace {

using Far::Index;

[[noreturn]] void refuse(int level, Index ev, const std::string& why) {
  throwUnsupported("the neighbourhood of refined vertex " + std::to_string(ev) + " at level " +
                   std::to_string(level) + " cannot be reduced to an extraordinary ring (" + why +
                   ")");
}

bool isSharpEdge(const Far::TopologyLevel& level, Index edge) {
  return level.IsEdgeInfSharp(edge) || level.IsEdgeBoundary(edge);
}

// Incomplete: the sparse level lacks faces around the vertex (nullopt from the caller's view).
// Otherwise the vertex must be smooth and regular, or lie on a straight sharp spoke/boundary.
enum class VertexCheck { kRegular, kIncomplete };

VertexCheck checkRingVertex(const Far::TopologyLevel& level, int levelIndex, Index v, bool onSpokeCrease,
                            bool onBoundary, Index ev) {
  if (v < 0) return VertexCheck::kIncomplete;
  int faces = level.GetVertexFaces(v).size(), edges = level.GetVertexEdges(v).size();
  if (level.IsVertexBoundary(v) != onBoundary) return VertexCheck::kIncomplete;
  if (faces != (onBoundary ? 2 : 4) || edges != (onBoundary ? 3 : 4)) return VertexCheck::kIncomplete;
  if (level.GetVertexSharpness(v) > 0.0f) refuse(levelIndex, ev, "a sharp vertex inside the ring");
  int sharpEdges = 0;
  for (Index edge : level.GetVertexEdges(v)) {
    bool sharp = isSharpEdge(level, edge);
    if (!sharp && level.GetEdgeSharpness(edge) > 0.0f) refuse(levelIndex, ev, "a semi-sharp crease inside the ring");
    sharpEdges += sharp ? 1 : 0;
  }
  if (sharpEdges != (onSpokeCrease || onBoundary ? 2 : 0)) refuse(levelIndex, ev, "a crease off the ring's spokes");
  return VertexCheck::kRegular;
}

std::optional<RingLayout> gatherAt(const RefinedLevels& levels, int levelIndex, Index ev) {
  const auto& level = levels.refiner.GetLevel(levelIndex);
  LatticeWalker walker(level);
  auto sectors = walker.sectorsAround(ev);
  if (!sectors) return std::nullopt;
  RingLayout ring;
  ring.shape = {static_cast<int>(sectors->faces.size()), sectors->open};
  std::vector<Index> vertices = walker.gather(*sectors, 2);
  for (Index v : vertices) {
    if (v < 0) return std::nullopt;
  }
  ring.sharpSpokes.assign(ring.shape.spokeCount(), 0);
  for (int j = 0; j < ring.shape.spokeCount(); ++j) {
    Index e = vertices[cer::ringIndex(j, cer::kE)], a = vertices[cer::ringIndex(j, cer::kA)];
    Index inner = level.FindEdge(ev, e), outer = level.FindEdge(e, a);
    if (inner < 0 || outer < 0) return std::nullopt;
    bool sharp = isSharpEdge(level, inner);
    if (sharp != isSharpEdge(level, outer)) refuse(levelIndex, ev, "a crease ends inside the ring");
    if (!sharp && level.GetEdgeSharpness(inner) > 0.0f) refuse(levelIndex, ev, "a semi-sharp spoke");
    ring.sharpSpokes[j] = sharp ? 1 : 0;
    bool boundarySpoke = ring.shape.open && (j == 0 || j == ring.shape.sectors);
    if (checkRingVertex(level, levelIndex, e, sharp && !boundarySpoke, boundarySpoke, ev) ==
        VertexCheck::kIncomplete) {
      return std::nullopt;
    }
  }
  for (int i = 0; i < ring.shape.sectors; ++i) {
    if (checkRingVertex(level, levelIndex, vertices[cer::ringIndex(i, cer::kD)], false, false, ev) ==
        VertexCheck::kIncomplete) {
      return std::nullopt;
    }
  }
  float evSharpness = level.GetVertexSharpness(ev);
  if (evSharpness > 0.0f && evSharpness < 10.0f) refuse(levelIndex, ev, "a semi-sharp corner");
  ring.cornerEv = evSharpness >= 10.0f;
  for (Index v : vertices) ring.points.push_back(levels.index(levelIndex, v));
  ring.sectorFaces = sectors->faces;
  ring.sectorRotations = sectors->rotation;
  return ring;
}

// Child face j of a quad lies at the parent's corner j and keeps that corner at local index j.
Index parentVertex(const Far::TopologyRefiner& refiner, int levelIndex, Index ev) {
  const auto& level = refiner.GetLevel(levelIndex);
  const auto& parent = refiner.GetLevel(levelIndex - 1);
  for (Index face : level.GetVertexFaces(ev)) {
    Index parentFace = level.GetFaceParentFace(face);
    auto children = parent.GetFaceChildFaces(parentFace);
    for (int j = 0; j < children.size(); ++j) {
      if (children[j] != face) continue;
      Index candidate = parent.GetFaceVertices(parentFace)[j];
      if (parent.GetVertexChildVertex(candidate) == ev) return candidate;
    }
  }
  return -1;
}

// The coarse ring's sector faces one level down; its points are refined by ringPoints.
RingLayout refinedOneStep(const Far::TopologyRefiner& refiner, int levelIndex, Index ev, RingLayout coarse) {
  const auto& parent = refiner.GetLevel(levelIndex - 1);
  RingLayout fine = std::move(coarse);
  fine.refinedOnce = true;
  for (int i = 0; i < fine.shape.sectors; ++i) {
    int rotation = fine.sectorRotations[i];
    fine.sectorFaces[i] = parent.GetFaceChildFaces(fine.sectorFaces[i])[rotation];
    if (fine.sectorFaces[i] < 0 || refiner.GetLevel(levelIndex).GetFaceVertices(fine.sectorFaces[i])[rotation] != ev) {
      refuse(levelIndex, ev, "the faces around it are missing from the refined level");
    }
  }
  return fine;
}

}  // namespace

RingLayout layoutRing(const RefinedLevels& levels, int level, Index ev) {
  if (auto ring = gatherAt(levels, level, ev)) return std::move(*ring);
  Index parentEv = level > 0 ? parentVertex(levels.refiner, level, ev) : -1;
  if (parentEv < 0) refuse(level, ev, "incomplete lattice");
  auto coarse = gatherAt(levels, level - 1, parentEv);
  if (!coarse) refuse(level, ev, "incomplete lattice one level up too");
  return refinedOneStep(levels.refiner, level, ev, std::move(*coarse));
}

std::vector<Vec3d> ringPoints(const RingLayout& ring, const std::vector<Vec3d>& refinedPositions) {
  std::vector<Vec3d> points;
  points.reserve(ring.points.size());
  for (int v : ring.points) points.push_back(refinedPositions[size_t(v)]);
  if (!ring.refinedOnce) return points;
  // One FAS step in single precision about the EV, as the rings are stored (patch_set.h).
  std::vector<float> relative;
  for (const Vec3d& p : points) {
    Vec3d d = p - points[0];
    relative.insert(relative.end(), {float(d.x), float(d.y), float(d.z)});
  }
  RingRules rules = makeRingRules(ring.shape, ring.sharpSpokes.data(), ring.cornerEv);
  std::vector<float> refined = refineRing(rules, relative.data(), 1);
  const Vec3d ev = points[0];
  for (int p = 0; p < ring.shape.ringPointCount(); ++p) {
    points[p] = ev + Vec3d(Vec3(refined[3 * p], refined[3 * p + 1], refined[3 * p + 2]));
  }
  return points;
}

}  // namespace tessera
