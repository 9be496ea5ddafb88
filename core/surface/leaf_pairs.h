// The pair bounds of the tree's exact leaves, tightened where a request first reads them
// (docs/ADAPTIVE.md §3c, §3d). The graded diagonal map and the flat projection were, computed
// for every leaf while preprocessing, most of a cold request's time (bigguy: 44 % of it), yet a
// request reads only the leaves its plan descends to. A leaf's tightened bounds feed no other
// node (ancestors read their leaves' nets, not their bounds), so computing them on first read
// gives every request the bounds the eager build gave, bit for bit.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "core/math/bezier_net.h"

namespace tessera {

struct SurfaceNode;
struct SurfaceTree;
struct PatchSet;

// A node's pair bound, its side bows and the diagonal they need (SurfaceNode's fields).
struct NodePair {
  float pair = 0;
  float bows[4] = {0, 0, 0, 0};
  uint8_t diagonal = 0;
};

// Per node, once tightened: its final NodePair. Thread-safe: concurrent requests for one mesh may
// tighten one leaf twice (the same values, deterministic), and the first to finish publishes it.
class LeafPairs {
 public:
  LeafPairs() = default;
  explicit LeafPairs(size_t nodes)
      : state_(std::make_unique<std::atomic<uint8_t>[]>(nodes)),
        pairs_(std::make_unique<NodePair[]>(nodes)),
        lowerBounds_(std::make_unique<float[]>(nodes)),
        size_(nodes) {}

  // Leaf `index`'s pairLowerBound (graded_pair_bound.h), rounded down: no tightening can take its
  // pair below it, so a request whose ε is under it need not tighten the leaf (set while building).
  void setLowerBound(uint32_t index, double lower);
  // Whether tightening leaf `index` could bring its pair within `epsilon`; false guarantees that
  // the tightened pair is above it.
  bool mayReach(uint32_t index, double epsilon) const { return lowerBounds_[index] <= epsilon * (1 + 1e-6); }

  // Leaf `index`'s tightened bounds: from `node` (its bounds at equal parameters) and its net.
  // `floor`: the tree's chain floor (SurfaceTree::floor).
  NodePair get(uint32_t index, const SurfaceNode& node, const BezierNet& net, double floor) const;
  // Tightened already (a cheap check, for callers that can skip fetching the net).
  bool known(uint32_t index) const { return state_[index].load(std::memory_order_acquire) == kDone; }
  NodePair cached(uint32_t index) const { return pairs_[index]; }
  size_t bytes() const { return size_ * (sizeof(std::atomic<uint8_t>) + sizeof(NodePair) + sizeof(float)); }

 private:
  static constexpr uint8_t kEmpty = 0, kWriting = 1, kDone = 2;
  std::unique_ptr<std::atomic<uint8_t>[]> state_;
  std::unique_ptr<NodePair[]> pairs_;
  std::unique_ptr<float[]> lowerBounds_;
  size_t size_ = 0;
};

// §3c then §3d on one exact leaf: the pair through a graded diagonal map where it may take off a
// fifth, then the flat projection, each kept where smaller than the bound so far.
NodePair tightenedLeafPair(const SurfaceNode& node, const BezierNet& net, double floor);

// The final pair bounds of any node of `tree`: an exact leaf's tightened on first read, every
// other node's as built.
NodePair pairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);

}  // namespace tessera
