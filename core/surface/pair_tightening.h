// The surface tree's pair bounds that wait for a request (docs/ADAPTIVE.md §1a): an internal
// node's direct bounds over its pieces (§3, §3a), an exact leaf's graded diagonal map and flat
// projection (§3c, §3d), and an internal node's diagonal map and flat projection over its
// descendants (§3b, §3d). Computed for every node while preprocessing they were most of a cold
// request's time (bigguy at 1e-3: 68 %), yet a request reads only the nodes its plan descends
// to, and needs a node's tighter pair only where its looser one is not within ε. Each is computed
// from what the build keeps (the nodes' exact corner values, the leaves' own bounds at equal
// parameters) in the order the eager build computed it, so a request gets the bounds that build
// gave, bit for bit.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/base/vec3.h"
#include "core/base/published_slots.h"
#include "core/base/zeroed_slots.h"
#include "core/math/bezier_net.h"

namespace tessera {

struct SurfaceTree;
struct PatchSet;

// A node's pair bound, its side bows and the diagonal they need (SurfaceNode's fields).
struct NodePair {
  float pair = 0;
  float bows[4] = {0, 0, 0, 0};
  uint8_t diagonal = 0;
};

// An internal node's direct bounds (§3 at equal parameters and §3a through its axis maps, over
// its pieces), before rounding to floats: what its ancestors' diagonal maps stand it in with
// (`own`, `ownBows`, at equal parameters, no twist) and what its own tightening starts from
// (`pair`, `bows`), and the node's pair fields from them (`fields`).
struct DirectBounds {
  double own = 0;
  std::array<double, 4> ownBows{};
  double pair = 0;
  std::array<double, 4> bows{};
  NodePair fields;
};

// A leaf's DirectBounds: its own bounds at equal parameters (no twist), its fields, and the pair
// and bows its own tightening starts from (the fields').
DirectBounds leafDirectBounds(const NodePair& fields, double own, const std::array<double, 4>& ownBows);

// What the build leaves for the pair bounds a request computes, and those bounds as requests
// compute them: an internal node's direct bounds (from its pieces), then, where deferred, the
// tightened ones. Thread-safe: concurrent requests for one mesh may compute one node's bounds
// twice (the same values, deterministic), and the first to finish publishes them.
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
  // An internal node, whose direct bounds always wait for a request (a leaf's are its own):
  // `lower` as in defer().
  void deferDirect(uint32_t node, double lower);
  // Per node, set by the build: its exact corner values (an EV bottom's own bounds the build
  // publishes as its DirectBounds; an exact leaf's and an internal node's wait for a request).
  std::vector<std::array<Vec3d, 4>> corners;
  double floor = 0;  // the tree's chain floor (SurfaceTree::floor)

  Deferred deferred(uint32_t node) const { return deferred_[node]; }
  // Whether tightening `node` could bring its pair within `epsilon`; false guarantees that the
  // tightened pair is above it (by the build's lower bound, or by a request that stopped
  // tightening once the pair went past its own ε, provenAbove).
  bool mayReach(uint32_t node, double epsilon) const {
    const double above = provenAbove(node);
    return lowerBounds_[node] <= epsilon * (1 + 1e-6) && !(above > 0 && epsilon <= above);
  }
  // A value the node's tightened pair is known to exceed; 0: none known.
  double provenAbove(uint32_t node) const {
    return std::atomic_ref(provenAbove_[node]).load(std::memory_order_relaxed);
  }
  // Keeps that the tightened pair exceeds `limit` (the largest such value known wins).
  void raiseProvenAbove(uint32_t node, double limit) const;
  bool known(uint32_t node) const { return pairs_.known(node); }
  NodePair cached(uint32_t node) const { return pairs_[node]; }
  // Publishes `pair` as node's tightened bounds unless another thread did first.
  void publish(uint32_t node, const NodePair& pair) const { pairs_.publish(node, pair); }
  bool directKnown(uint32_t node) const { return direct_.known(node); }
  const DirectBounds& directCached(uint32_t node) const { return direct_[node]; }
  // Publishes an internal node's direct bounds unless another thread did first.
  void publishDirect(uint32_t node, const DirectBounds& direct) const { direct_.publish(node, direct); }
  size_t bytes() const;

 private:
  static void roundDown(double lower, float& out);
  size_t size_ = 0;
  // What requests compute, per node: written for the few nodes a request reads.
  PublishedSlots<NodePair> pairs_;
  PublishedSlots<DirectBounds> direct_;
  ZeroedSlots<double> provenAbove_;
  std::vector<float> lowerBounds_;
  std::vector<Deferred> deferred_;
};

// An internal node's direct bounds, computed on first read and kept; a leaf's own bounds.
// `net`: an exact leaf's net (pieceNet) where the caller has it already.
DirectBounds directBoundsOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node,
                            const BezierNet* net = nullptr);
// The pair fields the build's direct bounds give (§3, §3a): the node's own fields, or an internal
// node's from its pieces on first read.
NodePair directPairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);

// The final pair bounds of any node of `tree`: tightened on first read where deferred.
NodePair pairOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);
// The same where the final pair can be within `limit`; none where it is proven above it. The
// tightening then stops as soon as every bound it takes the least of is past the limit (most
// nodes a plan tightens are still too coarse after it, and split), and keeps only that fact
// (provenAbove): a plan, which compares the pair with its ε, is the same either way.
std::optional<NodePair> pairWithin(const SurfaceTree& tree, const PatchSet& patches, uint32_t node, double limit);

}  // namespace tessera
