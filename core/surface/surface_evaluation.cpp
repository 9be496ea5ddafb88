#include "core/surface/surface_evaluation.h"

#include "core/math/bicubic.h"
#include "core/math/lanes.h"
#include "core/rings/fas.h"
#include "core/rings/ring_patches.h"

namespace tessera {

namespace {

BezierNet bsplineToRootBezier(const Vec3d* bspline, const Orientation& orientation, const Vec3d& offset) {
  Vec3d bezier[16];
  bsplineToBezier(bspline, bezier);
  for (Vec3d& p : bezier) p += offset;
  return orientNet(bezier, orientation);
}

}  // namespace

BezierNet pieceNet(const SurfaceTree& tree, const PatchSet& patches, uint32_t index) {
  const SurfaceNode& node = tree.nodes[index];
  const Orientation orientation = Orientation::fromCode(node.orientation);
  if (node.kind == NodeKind::kRegularLeaf) {
    Vec3d net[16];
    for (int k = 0; k < 16; ++k) net[k] = Vec3d(patches.regular.bspline[node.payload][k]);
    return bsplineToRootBezier(net, orientation, Vec3d());
  }
  const FasLeaf& leaf = tree.fasLeaves[node.payload];
  Vec3 relative[16];
  gatherFasLeafNet(tree, patches, node.payload, relative);
  Vec3d net[16];
  for (int k = 0; k < 16; ++k) net[k] = Vec3d(relative[k]);
  return bsplineToRootBezier(net, orientation, Vec3d(patches.rings.centers[leaf.ring]));
}

BezierNet netOrStandIn(const SurfaceTree& tree, const PatchSet& patches, uint32_t index, double& r) {
  const SurfaceNode& node = tree.nodes[index];
  r = 0;
  if (node.kind != NodeKind::kEvBottom) return pieceNet(tree, patches, index);
  const EvBottom& bottom = tree.evBottoms[node.payload];
  BezierNet g;
  for (int k = 0; k < 16; ++k) g[k] = Vec3d(bottom.g[k]) + Vec3d(bottom.center);
  r = node.standInBound;
  return g;
}

// Relative to the ring's centre: deep levels are tiny next to the model, and kept relative they
// keep their precision.
void gatherFasLeafNet(const SurfaceTree& tree, const PatchSet& patches, uint32_t fasLeaf, Vec3 net[16]) {
  const FasLeaf& leaf = tree.fasLeaves[fasLeaf];
  NetSource sources[16];
  sectorNetSources(patches.rings.rules(leaf.ring), leaf.sector, leaf.patch, sources);
  gatherNet(tree.refinedAtLevel(patches.rings, leaf.ring, leaf.level), sources, net);
}

BezierNet squareNet(const SurfaceTree& tree, const PatchSet& patches, const NodeSquare& leaf, int level, uint64_t ix,
                    uint64_t iy) {
  BezierNet net = pieceNet(tree, patches, leaf.node);
  for (int at = leaf.level; at < level; ++at) {
    const int d = level - at - 1;
    net = quadrantNet(net, int((ix >> d) & 1), int((iy >> d) & 1));
  }
  return net;
}

const Vec3* SurfaceEvaluator::fasNet(uint32_t fasLeaf) {
  if (cachedFas_ != fasLeaf) {
    gatherFasLeafNet(tree_, patches_, fasLeaf, cachedNet_);
    cachedFas_ = fasLeaf;
  }
  return cachedNet_;
}

// Ring pieces are evaluated relative to their ring's centre, then moved there.
inline PieceNet SurfaceEvaluator::leafNet(uint32_t index) {
  const SurfaceNode& node = tree_.nodes[index];
  if (node.kind == NodeKind::kEvBottom) {
    const EvBottom& bottom = tree_.evBottoms[node.payload];
    return {bottom.g.data(), true, 0, Vec3d(bottom.center)};
  }
  if (node.kind == NodeKind::kRegularLeaf) return {patches_.regular.bspline[node.payload].data(), false, node.orientation, Vec3d()};
  return {fasNet(node.payload), false, node.orientation, Vec3d(patches_.rings.centers[tree_.fasLeaves[node.payload].ring])};
}

SurfaceSample SurfaceEvaluator::evaluate(NodeSquare start, double u, double v) {
  const LeafPoint at = descendToLeaf(tree_.nodes.data(), start, u, v);
  return samplePiece<LaneVec3>(leafNet(at.leaf.node), at.x, at.y);
}

}  // namespace tessera
