#include "core/surface/leaf_pairs.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/bounds/flat_pair_bound.h"
#include "core/bounds/graded_pair_bound.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree.h"
#include "core/surface/surface_tree_builder.h"

namespace tessera {

namespace {

using surface_tree_building::roundUp;

// A leaf's pair is bounded through a graded map (§3c) where its bound at equal parameters is above
// kGradedFloor times the chain floor (10⁻⁴ of the diagonal, the finest relative tolerance the
// benchmarks ask) and more than kGradedSlack times the lower bound every pair bound has: elsewhere
// the map costs more than it can take off.
constexpr double kGradedFloor = 1000;
constexpr double kGradedSlack = 2;

// §3c, kept where smaller than §3's at equal parameters, and worth its cost only where it can take
// off a fifth at least.
void gradeLeafPair(SurfaceNode& node, const BezierNet& net, double floor) {
  if (!(node.pairBound > kGradedFloor * floor) || !(node.pairBound > kGradedSlack * pairLowerBound(net))) return;
  const std::optional<PairBounds> graded = gradedPairBounds(net, 0.8 * node.pairBound);
  if (!graded) return;
  const double pair = graded->pair * (1 + 1e-9);
  if (!(pair < node.pairBound)) return;
  node.pairBound = roundUp(pair);
  for (int side = 0; side < 4; ++side) node.sideBow[side] = roundUp(graded->bows[side] * (1 + 1e-9));
  node.pairDiagonal = graded->diagonal;
}

// §3d: a nearly flat piece's pair by projection onto one plane, kept where smaller.
void flattenLeafPair(SurfaceNode& node, const BezierNet& net) {
  const std::optional<FlatPairBound> flat = flatPairBound(net);
  const Vec3d corners[4] = {net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]], net[kCornerIndex[3]]};
  if (flat) surface_tree_building::keepFlatPair(node, *flat, corners);
}

}  // namespace

NodePair tightenedLeafPair(const SurfaceNode& node, const BezierNet& net, double floor) {
  SurfaceNode tightened = node;
  gradeLeafPair(tightened, net, floor);
  flattenLeafPair(tightened, net);
  return tightened.pairFields();
}

void LeafPairs::setLowerBound(uint32_t index, double lower) {
  const float f = float(lower);
  lowerBounds_[index] = double(f) > lower ? std::nextafter(f, 0.0f) : f;
}

NodePair LeafPairs::get(uint32_t index, const SurfaceNode& node, const BezierNet& net, double floor) const {
  if (known(index)) return pairs_[index];
  const NodePair pair = tightenedLeafPair(node, net, floor);
  uint8_t expected = kEmpty;
  if (state_[index].compare_exchange_strong(expected, kWriting, std::memory_order_acquire)) {
    pairs_[index] = pair;
    state_[index].store(kDone, std::memory_order_release);
  }
  return pair;
}

NodePair pairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t index) {
  const SurfaceNode& node = tree.nodes[index];
  if (!node.tightensOnRead()) return node.pairFields();
  if (tree.leafPairs.known(index)) return tree.leafPairs.cached(index);
  return tree.leafPairs.get(index, node, pieceNet(tree, patches, index), tree.floor);
}

}  // namespace tessera
