#include "core/surface_evaluation.h"

#include <cmath>
#include <iterator>

#include "core/bicubic.h"
#include "core/fas.h"
#include "core/lanes.h"
#include "core/ring_patches.h"

namespace tessera {

namespace {

// A FAS leaf's B-spline net relative to its ring's centre (deep levels are tiny next to the
// model: kept relative, they keep their precision).
void gatherFasNet(const RingSet& rings, const FasLeaf& leaf, const float* refined, Vec3d net[16]) {
  const RingRules rules = rings.rules(leaf.ring);
  NetSource sources[16];
  sectorNetSources(rules, leaf.sector, leaf.patch, sources);
  Vec3 relative[16];
  gatherNet(refined, sources, relative);
  for (int k = 0; k < 16; ++k) net[k] = Vec3d(relative[k]);
}

BezierNet bsplineToRootBezier(const Vec3d* bspline, const Orientation& orientation, const Vec3d& offset) {
  Vec3d bezier[16];
  bsplineToBezier(bspline, bezier);
  for (Vec3d& p : bezier) p += offset;
  return orientNet(bezier, orientation);
}

// Piece parameters of a point at (x, y) ∈ [0,1]² of the piece's square in root orientation.
void pieceParameters(const Orientation& o, double x, double y, double& s, double& t) {
  s = o.su * x + o.sv * y + (o.su + o.sv < 0 ? 1 : 0);
  t = o.tu * x + o.tv * y + (o.tu + o.tv < 0 ? 1 : 0);
}

// A unit vector across direction d (any, when d vanishes): the cross product with the axis d
// leans on least.
Vec3d anyNormalAcross(const Vec3d& d) {
  const Vec3d axis = std::abs(d.x) <= std::abs(d.y) && std::abs(d.x) <= std::abs(d.z) ? Vec3d(1, 0, 0)
                     : std::abs(d.y) <= std::abs(d.z)                                 ? Vec3d(0, 1, 0)
                                                                                      : Vec3d(0, 0, 1);
  const Vec3d n = cross(d, axis);
  const double l = length(n);
  return l > 0 ? n * (1.0 / l) : Vec3d(0, 0, 1);
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
  Vec3d net[16];
  gatherFasNet(patches.rings, leaf, tree.refinedAtLevel(patches.rings, leaf.ring, leaf.level), net);
  return bsplineToRootBezier(net, orientation, Vec3d(patches.rings.centers[leaf.ring]));
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

const Vec3d* SurfaceEvaluator::fasNet(uint32_t fasLeaf) {
  if (cachedFas_ != fasLeaf) {
    const FasLeaf& leaf = tree_.fasLeaves[fasLeaf];
    gatherFasNet(patches_.rings, leaf, tree_.refinedAtLevel(patches_.rings, leaf.ring, leaf.level), cachedNet_);
    cachedFas_ = fasLeaf;
  }
  return cachedNet_;
}

SurfaceSample SurfaceEvaluator::evaluateLeaf(const NodeSquare& leaf, double x, double y, size_t nudges) {
  const SurfaceNode& node = tree_.nodes[leaf.node];
  PatchSample p;
  Orientation orientation;
  // Ring pieces are evaluated relative to their ring's centre, then moved there.
  Vec3d offset;
  if (node.kind == NodeKind::kEvBottom) {
    const EvBottom& bottom = tree_.evBottoms[node.payload];
    Vec3d g[16];
    for (int k = 0; k < 16; ++k) g[k] = Vec3d(bottom.g[k]);
    p = evaluateBezier<Vec3d, LaneVec3>(g, x, y);
    offset = Vec3d(bottom.center);
  } else if (node.kind == NodeKind::kRegularLeaf) {
    orientation = Orientation::fromCode(node.orientation);
    double s, t;
    pieceParameters(orientation, x, y, s, t);
    p = evaluateBspline<Vec3, LaneVec3>(patches_.regular.bspline[node.payload].data(), s, t);
  } else {
    const FasLeaf& leaf = tree_.fasLeaves[node.payload];
    orientation = Orientation::fromCode(node.orientation);
    double s, t;
    pieceParameters(orientation, x, y, s, t);
    p = evaluateBspline<Vec3d, LaneVec3>(fasNet(node.payload), s, t);
    offset = Vec3d(patches_.rings.centers[leaf.ring]);
  }
  p.position += offset;
  // The normal's length found once: it is both the unit scale and the degeneracy test.
  const Vec3d n = cross(p.dPds, p.dPdt);
  const double l = length(n);
  if (!(l > 0)) {
    // A degenerate point (the derivatives vanish, as at a ring's corner, or are parallel, as on
    // the fold where a two-sided face meets a sharp corner): the normal of a point a step inside,
    // the steps growing toward the piece's centre; a piece degenerate throughout gets any unit
    // normal across its one direction.
    static constexpr double kSteps[] = {1e-6, 1e-3, 0.125, 0.5};
    if (nudges == std::size(kSteps)) return {p.position, anyNormalAcross(p.dPds + p.dPdt)};
    const double step = kSteps[nudges];
    const double nx = x + (x < 0.5 ? step : -step), ny = y + (y < 0.5 ? step : -step);
    return {p.position, evaluateLeaf(leaf, nx, ny, nudges + 1).normal};
  }
  return {p.position, n * (1.0 / l) * double(orientation.handedness())};
}

SurfaceSample SurfaceEvaluator::evaluate(NodeSquare at, double u, double v) {
  for (;;) {
    const double scale = exp2i(at.level);
    const double x = u * scale - double(at.ix), y = v * scale - double(at.iy);
    if (tree_.nodes[at.node].isLeaf()) return evaluateLeaf(at, std::clamp(x, 0.0, 1.0), std::clamp(y, 0.0, 1.0));
    at = at.child(tree_, (y >= 0.5 ? 2 : 0) + (x >= 0.5 ? 1 : 0));
  }
}

}  // namespace tessera
