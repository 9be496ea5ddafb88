// The direct pair bounds and side bows of the surface tree's internal nodes (docs/ADAPTIVE.md §3,
// §3a): every leaf below a node against the node's bilinear interpolant, at equal parameters and
// through the node's per-axis maps. Computed where a request first reads the node and kept
// (pair_tightening.h): a leaf meets only the ancestors a request reads, not all of its own.
#include <algorithm>
#include <bit>
#include <optional>

#include "core/bounds/axis_reparameterization.h"
#include "core/math/dyadic.h"
#include "core/surface/pair_tightening.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree_builder.h"

namespace tessera {

using surface_tree_building::roundUp;

namespace {

// The direct bounds of one internal node, gathered over its leaves depth first (the order the
// eager build met them: the cheap bounds skip leaves against the maxima so far).
class DirectGather {
 public:
  DirectGather(const SurfaceTree& tree, const PatchSet& patches, uint32_t node)
      : tree_(tree), patches_(patches), kept_(tree.tightening), node_(node), c_(kept_.corners[node]) {}

  DirectBounds compute();

 private:
  void gatherAxisSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, AxisMapBuilder& u,
                         AxisMapBuilder& v) const;
  void walk(uint32_t index, int depth, uint64_t ix, uint64_t iy);
  void leaf(uint32_t index, int depth, uint64_t ix, uint64_t iy);

  const SurfaceTree& tree_;
  const PatchSet& patches_;
  const PairTightening& kept_;
  const uint32_t node_;
  const std::array<Vec3d, 4>& c_;
  AxisMap u_, v_;  // the node's reparameterization of the geometric pair bound (§3a)
  double pair_ = 0, pairReparam_ = 0;
  std::array<double, 4> bows_{}, bowsReparam_{};
};

// The samples that pick a node's axis maps: its pieces' spans and, at their corners, where the
// surface projects onto the node's bilinear B across each axis. log2(kCells) levels down, every
// corner of a subtree that can sit on a breakpoint (a multiple of 1/kCells) is the subtree's
// own, so the walk stops there.
void DirectGather::gatherAxisSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, AxisMapBuilder& u,
                                     AxisMapBuilder& v) const {
  const SurfaceNode& node = tree_.nodes[index];
  constexpr int kSampleDepth = std::countr_zero(unsigned(AxisMap::kCells));
  if (!node.isLeaf() && depth < kSampleDepth) {
    for (int q = 0; q < 4; ++q) {
      gatherAxisSamples(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), u, v);
    }
    return;
  }
  const double size = exp2i(-depth), x0 = double(ix) * size, y0 = double(iy) * size;
  u.addPiece(x0, x0 + size);
  v.addPiece(y0, y0 + size);
  const double cx[4] = {x0, x0 + size, x0 + size, x0}, cy[4] = {y0, y0, y0 + size, y0 + size};
  for (int k = 0; k < 4; ++k) {
    const Vec3d& f = kept_.corners[index][k];
    // B's lines through the corner: across u (from u = 0 to 1) and across v.
    const Vec3d a = bilinearAt(c_.data(), 0, cy[k]), b = bilinearAt(c_.data(), 1, cy[k]);
    const Vec3d p = bilinearAt(c_.data(), cx[k], 0), q = bilinearAt(c_.data(), cx[k], 1);
    const double across = dot(b - a, b - a), along = dot(q - p, q - p);
    if (across > 0) u.addSample(cx[k], dot(f - a, b - a) / across);
    if (along > 0) v.addSample(cy[k], dot(f - p, q - p) / along);
  }
}

void DirectGather::walk(uint32_t index, int depth, uint64_t ix, uint64_t iy) {
  const SurfaceNode& node = tree_.nodes[index];
  if (node.isLeaf()) return leaf(index, depth, ix, iy);
  for (int q = 0; q < 4; ++q) walk(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1));
}

// A leaf's deviation from the node's bilinear interpolant B (restricted to the leaf, B is the
// bilinear of its values at the leaf's corners), and along the node's sides the leaf touches,
// from the node's chords; and the same through the node's axis maps (§3a: B at the preimages of
// the leaf's corners, the leaf's own net unchanged). First a cheap bound: the leaf's own bound
// (its deviation from its own bilinear) plus the largest gap between the two bilinears, at a leaf
// corner (their difference is bilinear); the de Casteljau bound only where the cheap one could
// raise the maximum.
void DirectGather::leaf(uint32_t index, int depth, uint64_t ix, uint64_t iy) {
  const SurfaceNode& node = tree_.nodes[index];
  double r = 0;
  std::optional<BezierNet> net;
  auto netOf = [&]() -> const BezierNet& {
    if (!net) net = netOrStandIn(tree_, patches_, index, r);
    return *net;
  };
  // An exact leaf's corners are its net's; an EV bottom's net is its stand-in, kept in floats.
  Vec3d own[4];
  if (node.kind == NodeKind::kEvBottom) netOf();
  for (int k = 0; k < 4; ++k) own[k] = net ? (*net)[kCornerIndex[k]] : kept_.corners[index][k];
  // An exact leaf's own bounds, computed from the net here the first time (not twice).
  if (node.kind != NodeKind::kEvBottom && !kept_.directKnown(index)) netOf();
  const DirectBounds leafOwn =
      directBoundsOf(tree_, patches_, index, node.kind != NodeKind::kEvBottom && net ? &*net : nullptr);
  const double ownPair = leafOwn.own;
  const std::array<double, 4>& ownBow = leafOwn.ownBows;
  const double scale = exp2i(-depth), x0 = double(ix) * scale, y0 = double(iy) * scale;
  const bool touches[4] = {y0 == 0, x0 + scale == 1, y0 + scale == 1, x0 == 0};
  auto against = [&](double u0, double u1, double v0, double v1, double& pair, std::array<double, 4>& bows) {
    Vec3d leafCorners[4];
    double gap2[4];  // squared: one square root for each maximum taken
    const double cx[4] = {u0, u1, u1, u0}, cy[4] = {v0, v0, v1, v1};
    for (int k = 0; k < 4; ++k) {
      leafCorners[k] = bilinearAt(c_.data(), cx[k], cy[k]);
      gap2[k] = lengthSquared(own[k] - leafCorners[k]);
    }
    const double cheap = ownPair + std::sqrt(*std::max_element(gap2, gap2 + 4));
    if (cheap > pair) pair = std::max(pair, std::min(cheap, r + splitNetDistance(netOf(), bilinearNet(leafCorners))));
    for (int side = 0; side < 4; ++side) {
      if (!touches[side]) continue;
      int from, to;
      sideCorners(side, from, to);
      const double cheapBow = ownBow[side] + std::sqrt(std::max(gap2[from], gap2[to]));
      if (cheapBow <= bows[side]) continue;
      const double bow = r + sideChordDistance(netOf(), side, leafCorners[from], leafCorners[to]);
      bows[side] = std::max(bows[side], std::min(cheapBow, bow));
    }
  };
  against(x0, x0 + scale, y0, y0 + scale, pair_, bows_);
  if (!u_.isIdentity() || !v_.isIdentity()) {
    against(u_.preimage(x0), u_.preimage(x0 + scale), v_.preimage(y0), v_.preimage(y0 + scale), pairReparam_,
            bowsReparam_);
  }
}

// At equal parameters or through the axis maps (§3a, whichever direct bound is smaller, each
// with the twist), against the stand-in's (§4), which the build set as the node's fields.
DirectBounds DirectGather::compute() {
  {
    AxisMapBuilder u, v;
    gatherAxisSamples(node_, 0, 0, 0, u, v);
    u_ = u.build(), v_ = v.build();
  }
  const SurfaceNode& self = tree_.nodes[node_];
  for (int q = 0; q < 4; ++q) walk(self.firstChild + q, 1, uint64_t(q & 1), uint64_t(q >> 1));
  DirectBounds out;
  out.own = pair_;
  out.ownBows = bows_;
  double pair = pair_;
  std::array<double, 4> bows = bows_;
  const bool reparam = !u_.isIdentity() || !v_.isIdentity();
  if (reparam && pairReparam_ < pair) pair = pairReparam_, bows = bowsReparam_;
  const double twist = length(c_[0] - c_[1] + c_[2] - c_[3]) / 4;
  out.pair = std::min(double(self.pairBound), (pair + twist) * (1 + 1e-9));
  for (int side = 0; side < 4; ++side) out.bows[side] = std::min(double(self.sideBow[side]), bows[side] * (1 + 1e-9));
  out.fields.pair = roundUp(out.pair);
  for (int side = 0; side < 4; ++side) out.fields.bows[side] = roundUp(out.bows[side]);
  return out;
}

}  // namespace

DirectBounds leafDirectBounds(const NodePair& fields, double own, const std::array<double, 4>& ownBows) {
  DirectBounds leaf;
  leaf.own = own;
  leaf.ownBows = ownBows;
  leaf.fields = fields;
  leaf.pair = leaf.fields.pair;
  std::copy(leaf.fields.bows, leaf.fields.bows + 4, leaf.bows.begin());
  return leaf;
}

// An EV bottom's bounds are the build's (published then); an exact leaf's (its net against the
// bilinear of its corners, surface_tree_building::standInPair) and an internal node's (from its
// pieces) are computed where first read and kept.
DirectBounds directBoundsOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t index,
                            const BezierNet* leafNet) {
  const PairTightening& kept = tree.tightening;
  const SurfaceNode& node = tree.nodes[index];
  if (kept.directKnown(index)) return kept.directCached(index);
  DirectBounds direct;
  if (node.isLeaf()) {
    const BezierNet net = leafNet ? *leafNet : pieceNet(tree, patches, index);
    const Vec3d corners[4] = {net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]], net[kCornerIndex[3]]};
    const surface_tree_building::StandInPair own = surface_tree_building::standInPair(net, corners, 0);
    direct = leafDirectBounds(own.fields, own.own, own.ownBows);
  } else {
    direct = DirectGather(tree, patches, index).compute();
  }
  kept.publishDirect(index, direct);
  return direct;
}

NodePair directPairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t index) {
  return directBoundsOf(tree, patches, index).fields;
}

}  // namespace tessera
