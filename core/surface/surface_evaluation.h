// The exact limit surface at any point of a root, through the surface tree: the leaf piece that
// holds the point (a regular B-spline patch, or a FAS patch refined from the ring kept at its
// level), or, within the deepest EV quadrant kept, its stand-in (within kChainFloor of the
// diagonal; exact at the EV itself, where the stand-in's corner is the limit position).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math/bezier_net.h"
#include "core/surface/surface_point.h"
#include "core/surface/surface_tree.h"

namespace tessera {

// The Bézier net, in root orientation, of a leaf (regular or FAS).
BezierNet pieceNet(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);
// A leaf's net (r = 0), or an EV bottom's stand-in g with its bound r: sup ‖f − g‖ ≤ r.
BezierNet netOrStandIn(const SurfaceTree& tree, const PatchSet& patches, uint32_t node, double& r);
// FAS leaf `fasLeaf`'s B-spline net in its piece frame, relative to its ring's centre, as
// evaluation reads it (gathered from the ring's refined level).
void gatherFasLeafNet(const SurfaceTree& tree, const PatchSet& patches, uint32_t fasLeaf, Vec3 net[16]);
// The net of square (level, ix, iy) at or below `leaf`'s square: the leaf's net halved by
// de Casteljau down to it.
BezierNet squareNet(const SurfaceTree& tree, const PatchSet& patches, const NodeSquare& leaf, int level, uint64_t ix,
                    uint64_t iy);

// Evaluates points of one root, starting from a node known to hold them. Keeps the last FAS
// patch it gathered.
class SurfaceEvaluator {
 public:
  SurfaceEvaluator(const SurfaceTree& tree, const PatchSet& patches) : tree_(tree), patches_(patches) {}

  // (u, v) in root coordinates, inside `start`'s square.
  SurfaceSample evaluate(NodeSquare start, double u, double v);

 private:
  PieceNet leafNet(uint32_t node);
  const Vec3* fasNet(uint32_t fasLeaf);

  const SurfaceTree& tree_;
  const PatchSet& patches_;
  uint32_t cachedFas_ = kNoNode;
  Vec3 cachedNet_[16];  // relative to the ring's centre
};

}  // namespace tessera
