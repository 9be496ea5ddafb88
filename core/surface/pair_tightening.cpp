#include "core/surface/pair_tightening.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>

#include "core/bounds/diagonal_pair_bound.h"
#include "core/bounds/diagonal_reparameterization.h"
#include "core/bounds/flat_pair_bound.h"
#include "core/bounds/graded_pair_bound.h"
#include "core/math/bicubic.h"
#include "core/math/dyadic.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree.h"
#include "core/surface/surface_tree_builder.h"

namespace tessera {

using surface_tree_building::kDiagonalFloor;
using surface_tree_building::kDiagonalReach;
using surface_tree_building::kFlatReach;
using surface_tree_building::roundUp;

PairTightening::PairTightening(size_t nodes)
    : corners(nodes),
      size_(nodes),
      pairs_(nodes),
      direct_(nodes),
      provenAbove_(nodes),
      lowerBounds_(nodes, 0),
      deferred_(nodes, Deferred::kNone) {}

void PairTightening::roundDown(double lower, float& out) {
  const float f = float(lower);
  out = double(f) > lower ? std::nextafter(f, 0.0f) : f;
}

void PairTightening::defer(uint32_t node, Deferred what, double lower) {
  deferred_[node] = what;
  roundDown(lower, lowerBounds_[node]);
}

void PairTightening::deferDirect(uint32_t node, double lower) {
  roundDown(lower, lowerBounds_[node]);
}

void PairTightening::raiseProvenAbove(uint32_t node, double limit) const {
  const std::atomic_ref known(provenAbove_[node]);
  double was = known.load(std::memory_order_relaxed);
  while (was < limit && !known.compare_exchange_weak(was, limit, std::memory_order_relaxed)) {
  }
}

size_t PairTightening::bytes() const {
  const size_t perNode = sizeof(std::array<Vec3d, 4>) + PublishedSlots<NodePair>::kBytesPerSlot +
                         PublishedSlots<DirectBounds>::kBytesPerSlot + sizeof(double) + sizeof(float) +
                         sizeof(Deferred);
  return sizeof(*this) + size_ * perNode;
}

namespace {

// A leaf's pair is bounded through a graded map (§3c) where its bound at equal parameters is above
// kGradedFloor times the chain floor (10⁻⁴ of the diagonal, the finest relative tolerance the
// benchmarks ask) and more than kGradedSlack times the lower bound every pair bound has: elsewhere
// the map costs more than it can take off.
constexpr double kGradedFloor = 1000;
constexpr double kGradedSlack = 2;

// A node's tightened pair, from the tree, its patches and what the build kept.
class Tightener {
 public:
  Tightener(const SurfaceTree& tree, const PatchSet& patches)
      : tree_(tree), patches_(patches), kept_(tree.tightening) {}

  // Each none where the pair is proven above `limit` (pairWithin).
  std::optional<NodePair> leaf(uint32_t index, double limit) const;
  std::optional<NodePair> internal(uint32_t index, double limit) const;

 private:
  void gatherGridSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, Vec3d* grid) const;
  DiagonalMap diagonalMap(uint32_t index) const;
  void againstDiagonal(uint32_t index, int depth, uint64_t ix, uint64_t iy, const DiagonalMap& map, double& pair,
                       std::array<double, 4>& bows, double abortAbove) const;
  void gatherFlat(uint32_t index, int depth, uint64_t ix, uint64_t iy, FlatGather& gather) const;
  std::optional<FlatPairBound> flatBound(uint32_t index) const;

  const SurfaceTree& tree_;
  const PatchSet& patches_;
  const PairTightening& kept_;
};

// Takes a flat bound where it beats the pair so far (keepFlatBound), rounded up to floats.
void keepFlat(const FlatPairBound& flat, const Vec3d corners[4], NodePair& pair) {
  PairBounds bounds{pair.pair, {pair.bows[0], pair.bows[1], pair.bows[2], pair.bows[3]}, pair.diagonal};
  if (!keepFlatBound(flat, corners, bounds)) return;
  pair.pair = roundUp(bounds.pair);
  for (int side = 0; side < 4; ++side) pair.bows[side] = roundUp(bounds.bows[side]);
  pair.diagonal = bounds.diagonal;
}

// Whether §3d's bound, kept, can bring the pair within `limit` (it is grown by 1 + 1e-9): where
// neither it nor the bound so far can, the tightening may stop at the limit.
bool within(double bound, double limit) { return bound * (1 + 1e-9) <= limit; }

// §3c, kept where smaller than §3's at equal parameters and worth its cost (it may take off a
// fifth at least), then §3d, kept where smaller still. §3c's walk, the dear part, stops at
// `limit` when neither §3's bound nor §3d's is within it (the least of the three is then above).
std::optional<NodePair> Tightener::leaf(uint32_t index, double limit) const {
  const BezierNet net = pieceNet(tree_, patches_, index);
  NodePair pair = directBoundsOf(tree_, patches_, index, &net).fields;
  const std::optional<FlatPairBound> flat = flatPairBound(net);
  const bool stops = pair.pair > limit && !(flat && within(flat->pair, limit));
  if (pair.pair > kGradedFloor * kept_.floor && pair.pair > kGradedSlack * pairLowerBound(net)) {
    const std::optional<PairBounds> graded = gradedPairBounds(net, 0.8 * pair.pair, stops ? limit : INFINITY);
    const double bound = graded ? graded->pair * (1 + 1e-9) : INFINITY;
    if (bound < pair.pair) {
      pair.pair = roundUp(bound);
      for (int side = 0; side < 4; ++side) pair.bows[side] = roundUp(graded->bows[side] * (1 + 1e-9));
      pair.diagonal = graded->diagonal;
    }
  }
  const Vec3d corners[4] = {net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]], net[kCornerIndex[3]]};
  if (flat) keepFlat(*flat, corners, pair);
  if (stops && pair.pair > limit) return std::nullopt;
  return pair;
}

// The surface at the grid points (i, j) / kCells of a node (index i + kPoints j) for its diagonal
// maps: corners of its descendants kCells levels down, or points of a leaf above that.
void Tightener::gatherGridSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, Vec3d* grid) const {
  constexpr int kGridDepth = std::countr_zero(unsigned(DiagonalMap::kCells));
  const SurfaceNode& node = tree_.nodes[index];
  if (depth < kGridDepth && !node.isLeaf()) {
    for (int q = 0; q < 4; ++q) {
      gatherGridSamples(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), grid);
    }
    return;
  }
  const int span = DiagonalMap::kCells >> depth;  // grid cells along the node's side
  const int i0 = int(ix) * span, j0 = int(iy) * span;
  if (depth == kGridDepth) {
    for (int c = 0; c < 4; ++c) grid[i0 + (c == 1 || c == 2) + DiagonalMap::kPoints * (j0 + (c >= 2))] = kept_.corners[index][c];
    return;
  }
  double r;
  const BezierNet net = netOrStandIn(tree_, patches_, index, r);
  for (int b = 0; b <= span; ++b) {
    for (int a = 0; a <= span; ++a) {
      grid[i0 + a + DiagonalMap::kPoints * (j0 + b)] = evaluateBezier(net.data(), double(a) / span, double(b) / span).position;
    }
  }
}

// The diagonal whose pair, through its map, lies nearer the surface at the grid points.
DiagonalMap Tightener::diagonalMap(uint32_t index) const {
  Vec3d grid[DiagonalMap::kPoints * DiagonalMap::kPoints];
  gatherGridSamples(index, 0, 0, 0, grid);
  const Vec3d* c = kept_.corners[index].data();
  const DiagonalMap first(0, c, grid), second(1, c, grid);
  return second.gridGap() < first.gridGap() ? second : first;
}

// §3b over the pieces of a node, in the order the build met them (depth first): each leaf up to
// kDiagonalReach levels down with its net, and each node kDiagonalReach + 1 levels down standing
// for its leaves with its corners and direct bounds, so a leaf costs the diagonal bound at most
// kDiagonalReach ancestors, however deep the tree. The cheap bounds skip pieces against the
// maxima so far, which is why the order is the build's.
void Tightener::againstDiagonal(uint32_t index, int depth, uint64_t ix, uint64_t iy, const DiagonalMap& map,
                                double& pair, std::array<double, 4>& bows, double abortAbove) const {
  if (pair > abortAbove) return;
  const SurfaceNode& node = tree_.nodes[index];
  const double scale = exp2i(-depth), x0 = double(ix) * scale, y0 = double(iy) * scale;
  if (depth == kDiagonalReach + 1) {
    const std::array<Vec3d, 4>& c = kept_.corners[index];
    const DirectBounds own = directBoundsOf(tree_, patches_, index);
    const std::array<double, 4>& b = own.ownBows;
    const LeafOwn stand{{c[0], c[1], c[2], c[3]}, x0, y0, scale, own.own, {b[0], b[1], b[2], b[3]}};
    return pieceAgainstDiagonal(nullptr, 0, stand, x0, y0, scale, map, pair, bows, abortAbove);
  }
  if (!node.isLeaf()) {
    for (int q = 0; q < 4; ++q) {
      againstDiagonal(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), map, pair, bows,
                      abortAbove);
    }
    return;
  }
  double r;
  const BezierNet net = netOrStandIn(tree_, patches_, index, r);
  const BezierNet* exactNet = node.kind != NodeKind::kEvBottom ? &net : nullptr;
  const DirectBounds leafOwn = directBoundsOf(tree_, patches_, index, exactNet);
  const std::array<double, 4>& b = leafOwn.ownBows;
  const LeafOwn own{{net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]], net[kCornerIndex[3]]},
                    x0, y0, scale, leafOwn.own, {b[0], b[1], b[2], b[3]}};
  const LazyNet whole(net);
  pieceAgainstDiagonal(&whole, r, own, x0, y0, scale, map, pair, bows, abortAbove);
}

// §3d over a node of several pieces: its descendants kFlatReach levels down stand in with their
// corners grown by their direct pair bounds (not their tightened ones, which would tighten, level
// by level, every node below the first one a request reads: most of the tree at 10⁻³), and
// along the node's sides with their corners grown by their bows; leaves above that with their
// nets (EV bottoms' stand-ins grown by r).
void Tightener::gatherFlat(uint32_t index, int depth, uint64_t ix, uint64_t iy, FlatGather& gather) const {
  const SurfaceNode& node = tree_.nodes[index];
  const uint8_t on = sidesTouched(ix, iy, depth);
  if (!node.isLeaf() && depth < kFlatReach) {
    for (int q = 0; q < 4; ++q) {
      gatherFlat(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), gather);
    }
    return;
  }
  if (!node.isLeaf()) {
    const NodePair stands = directPairOf(tree_, patches_, index);
    const std::array<Vec3d, 4>& c = kept_.corners[index];
    for (int k = 0; k < 4; ++k) {
      gather.addPoint(c[k], stands.pair);
      if (!(on >> k & 1)) continue;
      gather.addSidePoint(k, c[k], stands.bows[k]);
      gather.addSidePoint(k, c[(k + 1) % 4], stands.bows[k]);
    }
    return;
  }
  double r;
  const BezierNet net = netOrStandIn(tree_, patches_, index, r);
  gather.addNet(net, r, on);
}

std::optional<FlatPairBound> Tightener::flatBound(uint32_t index) const {
  const Vec3d* corners = kept_.corners[index].data();
  FlatGather gather(corners);
  if (!gather.valid()) return std::nullopt;
  gatherFlat(index, 0, 0, 0, gather);
  return gather.bound();
}

// §3b through the node's diagonal map where its pair bound is smaller than the direct one (no
// twist, that diagonal only, with its own bows), then §3d where the pair is still above
// kDiagonalFloor chain floors. The walk of §3b, the dear part, stops at `limit` when neither the
// direct bound nor §3d's is within it (§3d is then computed first: it is computed after §3b
// wherever the pair stays above the limit, and the limits a plan passes are far above that floor).
std::optional<NodePair> Tightener::internal(uint32_t index, double limit) const {
  const DirectBounds direct = directBoundsOf(tree_, patches_, index);
  std::optional<FlatPairBound> flat;
  bool flatKnown = false;
  bool stops = false;
  if (direct.pair > limit && limit > kDiagonalFloor * kept_.floor) {
    flat = flatBound(index), flatKnown = true;
    stops = !(flat && within(flat->pair, limit));
  }
  const DiagonalMap map = diagonalMap(index);
  // Its value at the grid points starts the maximum: the cheap bounds then skip more pieces.
  double diagonalPair = map.gridGap();
  std::array<double, 4> diagonalBows = {0, 0, 0, 0};
  const double abortAbove = stops ? limit : INFINITY;
  const SurfaceNode& node = tree_.nodes[index];
  for (int q = 0; q < 4; ++q) {
    againstDiagonal(node.firstChild + q, 1, uint64_t(q & 1), uint64_t(q >> 1), map, diagonalPair, diagonalBows, abortAbove);
  }
  if (diagonalPair > abortAbove) return std::nullopt;
  double bound = direct.pair;
  std::array<double, 4> bows = direct.bows;
  uint8_t kept = 0;
  if (diagonalPair < bound) {
    bound = diagonalPair * (1 + 1e-9), kept = uint8_t(1 + map.diagonal());
    for (int side = 0; side < 4; ++side) bows[side] = diagonalBows[side] * (1 + 1e-9);
  }
  NodePair pair;
  pair.pair = roundUp(bound);
  for (int side = 0; side < 4; ++side) pair.bows[side] = roundUp(bows[side]);
  pair.diagonal = kept;
  if (pair.pair > kDiagonalFloor * kept_.floor) {
    if (!flatKnown) flat = flatBound(index);
    if (flat) keepFlat(*flat, kept_.corners[index].data(), pair);
  }
  if (stops && pair.pair > limit) return std::nullopt;
  return pair;
}

}  // namespace

std::optional<NodePair> pairWithin(const SurfaceTree& tree, const PatchSet& patches, uint32_t index, double limit) {
  const PairTightening& tightening = tree.tightening;
  const PairTightening::Deferred deferred = tightening.deferred(index);
  if (deferred == PairTightening::Deferred::kNone) return directPairOf(tree, patches, index);
  if (tightening.known(index)) return tightening.cached(index);
  const double above = tightening.provenAbove(index);
  if (above > 0 && limit <= above) return std::nullopt;
  const Tightener tightener(tree, patches);
  const std::optional<NodePair> pair =
      deferred == PairTightening::Deferred::kLeaf ? tightener.leaf(index, limit) : tightener.internal(index, limit);
  if (!pair) {
    tightening.raiseProvenAbove(index, limit);
    return std::nullopt;
  }
  tightening.publish(index, *pair);
  return pair;
}

NodePair pairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t index) {
  return *pairWithin(tree, patches, index, INFINITY);
}

}  // namespace tessera
