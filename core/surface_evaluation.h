// The exact limit surface at any point of a root, through the surface tree: the leaf piece that
// holds the point (a regular B-spline patch, or a FAS patch refined from the ring kept at its
// level), or, within the deepest EV quadrant kept, its stand-in (within kChainFloor of the
// diagonal; exact at the EV itself, where the stand-in's corner is the limit position).
#pragma once

#include <cstdint>
#include <vector>

#include "core/bezier_net.h"
#include "core/dyadic.h"
#include "core/surface_tree.h"

namespace tessera {

// A node's square in its root: [ix, ix + 1] × [iy, iy + 1] scaled by 2^-level.
struct NodeSquare {
  uint32_t node = kNoNode;
  int level = 0;
  uint64_t ix = 0, iy = 0;

  NodeSquare child(const SurfaceTree& tree, int q) const {
    return {tree.nodes[node].firstChild + uint32_t(q), level + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1)};
  }
  double size() const { return exp2i(-level); }
};

// The Bézier net, in root orientation, of a leaf (regular or FAS).
BezierNet pieceNet(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);
// The net of square (level, ix, iy) at or below `leaf`'s square: the leaf's net halved by
// de Casteljau down to it.
BezierNet squareNet(const SurfaceTree& tree, const PatchSet& patches, const NodeSquare& leaf, int level, uint64_t ix,
                    uint64_t iy);

struct SurfaceSample {
  Vec3d position;
  Vec3d normal;  // unit; oriented like the mesh (counter-clockwise faces seen from it)
};

// Evaluates points of one root, starting from a node known to hold them. Keeps the last FAS
// patch it gathered.
class SurfaceEvaluator {
 public:
  SurfaceEvaluator(const SurfaceTree& tree, const PatchSet& patches) : tree_(tree), patches_(patches) {}

  // (u, v) in root coordinates, inside `start`'s square.
  SurfaceSample evaluate(NodeSquare start, double u, double v);

 private:
  SurfaceSample evaluateLeaf(const NodeSquare& leaf, double x, double y, size_t nudges = 0);
  const Vec3d* fasNet(uint32_t fasLeaf);

  const SurfaceTree& tree_;
  const PatchSet& patches_;
  uint32_t cachedFas_ = kNoNode;
  Vec3d cachedNet_[16];  // relative to the ring's centre
};

}  // namespace tessera
