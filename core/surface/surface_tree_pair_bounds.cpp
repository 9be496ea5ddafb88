// The direct pair bounds and side bows of the surface tree's nodes (docs/ADAPTIVE.md §3, §3a),
// gathered leaf by leaf down each root: at equal parameters and through each node's per-axis maps.
// The dearer ones (§3b's diagonal maps, §3c, §3d) wait for a request (pair_tightening.h).
#include <algorithm>
#include <bit>

#include "core/bounds/graded_pair_bound.h"
#include "core/math/bicubic.h"
#include "core/math/dyadic.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree_builder.h"

namespace tessera::surface_tree_building {

// A leaf's deviation from each ancestor's bilinear interpolant B (restricted to the leaf, B is the
// bilinear of its values at the leaf's corners), and along the ancestor's sides the leaf touches,
// from the ancestor's chords; and the same through the ancestor's axis maps (§3a: B at the
// preimages of the leaf's corners, the leaf's own net unchanged). First a cheap bound: the
// leaf's deviation from its own bilinear plus the largest gap between the two bilinears, at a
// leaf corner (their difference is bilinear); the de Casteljau bound only where the cheap one
// could raise the maximum.
void TreeBuilder::leafAgainstAncestors(uint32_t index, const BezierNet& net, double r, int level, uint64_t ix,
                                       uint64_t iy, const std::vector<Ancestor>& path) {
  Vec3d own[4];
  for (int k = 0; k < 4; ++k) own[k] = net[kCornerIndex[k]];
  const double ownPair = r + splitNetDistance(net, bilinearNet(own));
  double ownBow[4];
  const std::array<double, 4> chord = chordBows(net, own);
  for (int side = 0; side < 4; ++side) ownBow[side] = r + chord[side];
  // The leaf's own bounds, for the diagonal bounds of its ancestors (pair_tightening.h).
  pair_[index] = ownPair;
  std::copy(ownBow, ownBow + 4, bow_[index].begin());
  for (const Ancestor& a : path) {
    const std::array<Vec3d, 4>& c = corners_[a.node];
    double x0, y0, scale;
    a.square(level, ix, iy, x0, y0, scale);
    const bool touches[4] = {y0 == 0, x0 + scale == 1, y0 + scale == 1, x0 == 0};
    // The leaf against B at the same parameters, or against B at the preimage of its corners.
    auto against = [&](double u0, double u1, double v0, double v1, double& pair, std::array<double, 4>& bows) {
      Vec3d leafCorners[4];
      double gap[4];
      const double cx[4] = {u0, u1, u1, u0}, cy[4] = {v0, v0, v1, v1};
      for (int k = 0; k < 4; ++k) {
        leafCorners[k] = bilinearAt(c.data(), cx[k], cy[k]);
        gap[k] = length(own[k] - leafCorners[k]);
      }
      const double cheap = ownPair + *std::max_element(gap, gap + 4);
      if (cheap > pair) pair = std::max(pair, std::min(cheap, r + splitNetDistance(net, bilinearNet(leafCorners))));
      for (int side = 0; side < 4; ++side) {
        if (!touches[side]) continue;
        int from, to;
        sideCorners(side, from, to);
        const double cheapBow = ownBow[side] + std::max(gap[from], gap[to]);
        if (cheapBow <= bows[side]) continue;
        const double bow = r + sideChordDistance(net, side, leafCorners[from], leafCorners[to]);
        bows[side] = std::max(bows[side], std::min(cheapBow, bow));
      }
    };
    against(x0, x0 + scale, y0, y0 + scale, pair_[a.node], bow_[a.node]);
    if (!a.u.isIdentity() || !a.v.isIdentity()) {
      against(a.u.preimage(x0), a.u.preimage(x0 + scale), a.v.preimage(y0), a.v.preimage(y0 + scale),
              pairReparam_[a.node], bowReparam_[a.node]);
    }
  }
}

// The samples that pick a node's axis maps: its pieces' spans and, at their corners, where the
// surface projects onto the node's bilinear B across each axis. log2(kCells) levels down, every
// corner of a subtree that can sit on a breakpoint (a multiple of 1/kCells) is the subtree's
// own, so the walk stops there.
void TreeBuilder::gatherAxisSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, const std::array<Vec3d, 4>& c,
                                    AxisMapBuilder& u, AxisMapBuilder& v) const {
  const SurfaceNode& node = tree_.nodes[index];
  constexpr int kSampleDepth = std::countr_zero(unsigned(AxisMap::kCells));
  if (!node.isLeaf() && depth < kSampleDepth) {
    for (int q = 0; q < 4; ++q) {
      gatherAxisSamples(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), c, u, v);
    }
    return;
  }
  const double size = exp2i(-depth), x0 = double(ix) * size, y0 = double(iy) * size;
  u.addPiece(x0, x0 + size);
  v.addPiece(y0, y0 + size);
  const double cx[4] = {x0, x0 + size, x0 + size, x0}, cy[4] = {y0, y0, y0 + size, y0 + size};
  for (int k = 0; k < 4; ++k) {
    const Vec3d& f = corners_[index][k];
    // B's lines through the corner: across u (from u = 0 to 1) and across v.
    const Vec3d a = bilinearAt(c.data(), 0, cy[k]), b = bilinearAt(c.data(), 1, cy[k]);
    const Vec3d p = bilinearAt(c.data(), cx[k], 0), q = bilinearAt(c.data(), cx[k], 1);
    const double across = dot(b - a, b - a), along = dot(q - p, q - p);
    if (across > 0) u.addSample(cx[k], dot(f - a, b - a) / across);
    if (along > 0) v.addSample(cy[k], dot(f - p, q - p) / along);
  }
}

void TreeBuilder::directPairBounds(uint32_t index, int level, uint64_t ix, uint64_t iy, std::vector<Ancestor>& path) {
  const SurfaceNode& node = tree_.nodes[index];
  if (node.isLeaf()) {
    double r;
    const BezierNet net = netOrStandIn(tree_, patches_, index, r);
    leafAgainstAncestors(index, net, r, level, ix, iy, path);
    return;
  }
  {
    AxisMapBuilder u, v;
    gatherAxisSamples(index, 0, 0, 0, corners_[index], u, v);
    path.push_back({index, level, ix, iy, u.build(), v.build()});
  }
  const bool reparam = !path.back().u.isIdentity() || !path.back().v.isIdentity();
  for (int q = 0; q < 4; ++q) {
    directPairBounds(node.firstChild + q, level + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), path);
  }
  path.pop_back();
  // At equal parameters or through the axis maps (§3a, whichever direct bound is smaller, each
  // with the twist), against the stand-in's (§4). Where the node is coarser than kDiagonalFloor,
  // its diagonal map (§3b) and flat projection (§3d) may take off more: deferred.
  SurfaceNode& self = tree_.nodes[index];
  const std::array<Vec3d, 4>& c = corners_[index];
  const double twist = length(c[0] - c[1] + c[2] - c[3]) / 4;
  double pair = pair_[index];
  std::array<double, 4> bows = bow_[index];
  if (reparam && pairReparam_[index] < pair) pair = pairReparam_[index], bows = bowReparam_[index];
  pair = std::min(double(self.pairBound), (pair + twist) * (1 + 1e-9));
  for (int side = 0; side < 4; ++side) bows[side] = std::min(double(self.sideBow[side]), bows[side] * (1 + 1e-9));
  if (self.pairBound > kDiagonalFloor * floor_) {
    // The surface's centre is the corner all four children share.
    tree_.tightening.defer(index, PairTightening::Deferred::kInternal, pairLowerBound(c.data(), corners_[self.firstChild][2]));
    tree_.tightening.setDirect(index, pair, bows);
  }
  self.pairBound = roundUp(pair);
  for (int side = 0; side < 4; ++side) self.sideBow[side] = roundUp(bows[side]);
  self.pairDiagonal = 0;
}

}  // namespace tessera::surface_tree_building
