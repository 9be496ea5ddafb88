// The surface tree's dearest pair bounds, computed where a request first reads them
// (docs/ADAPTIVE.md §3b, §3c, §3d): an exact leaf's graded diagonal map and flat projection, and
// an internal node's diagonal map and flat projection over its descendants. Computed for every
// node while preprocessing they were most of a cold request's time (bigguy at 1e-3: 68 %), yet
// a request reads only the nodes its plan descends to, and needs a node's tightened pair only
// where it may be within ε. Each is computed from what the build keeps (the nodes' exact corner
// values and their direct bounds at equal parameters) in the order the build computed it, so a
// request gets the bounds the eager build gave, bit for bit.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/base/vec3.h"

namespace tessera {

struct SurfaceTree;
struct PatchSet;

// A node's pair bound, its side bows and the diagonal they need (SurfaceNode's fields).
struct NodePair {
  float pair = 0;
  float bows[4] = {0, 0, 0, 0};
  uint8_t diagonal = 0;
};

// What the build leaves for the tightening, and the tightened pairs as requests compute them.
// Thread-safe: concurrent requests for one mesh may tighten one node twice (the same values,
// deterministic), and the first to finish publishes it.
class PairTightening {
 public:
  enum class Deferred : uint8_t {
    kNone,      // the node's fields are final
    kLeaf,      // an exact leaf: §3c, §3d on its net
    kInternal,  // an internal node with a diagonal map: §3b over its pieces, then §3d
  };

  PairTightening() = default;
  explicit PairTightening(size_t nodes);

  // Set while building. `lower`: a lower bound of every pair bound of the node (the surface's
  // centre against the pair's planes), rounded down here.
  void defer(uint32_t node, Deferred what, double lower);
  // An internal node's bounds after §3 and §3a, before rounding to floats (the diagonal map
  // compares against them).
  void setDirect(uint32_t node, double pair, const std::array<double, 4>& bows);
  // Per node (moved in by the build): its exact corner values, and its direct bounds at equal
  // parameters (a leaf's own; an internal node's gathered from its pieces), which it stands in
  // with for its pieces.
  std::vector<std::array<Vec3d, 4>> corners;
  std::vector<double> ownPair;
  std::vector<std::array<double, 4>> ownBows;
  double floor = 0;  // the tree's chain floor (SurfaceTree::floor)

  Deferred deferred(uint32_t node) const { return deferred_[node]; }
  // Whether tightening `node` could bring its pair within `epsilon`; false guarantees that the
  // tightened pair is above it.
  bool mayReach(uint32_t node, double epsilon) const { return lowerBounds_[node] <= epsilon * (1 + 1e-6); }
  bool known(uint32_t node) const { return state_[node].load(std::memory_order_acquire) == kDone; }
  NodePair cached(uint32_t node) const { return pairs_[node]; }
  // Publishes `pair` as node's tightened bounds unless another thread did first.
  void publish(uint32_t node, const NodePair& pair) const;
  double directPair(uint32_t node) const { return directPair_[node]; }
  const std::array<double, 4>& directBows(uint32_t node) const { return directBows_[node]; }
  size_t bytes() const;

 private:
  static constexpr uint8_t kEmpty = 0, kWriting = 1, kDone = 2;
  size_t size_ = 0;
  std::unique_ptr<std::atomic<uint8_t>[]> state_;
  std::unique_ptr<NodePair[]> pairs_;
  std::vector<float> lowerBounds_;
  std::vector<Deferred> deferred_;
  std::vector<double> directPair_;
  std::vector<std::array<double, 4>> directBows_;
};

// The final pair bounds of any node of `tree`: tightened on first read where deferred.
NodePair pairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);

}  // namespace tessera
