// The builder of the surface tree (surface_tree.h) and the constants the pair bounds it defers
// share (pair_tightening.h): surface_tree.cpp builds the quadtree and each node's stand-in and
// curvature bounds; direct_pair_bounds.cpp and pair_tightening.cpp compute the pair bounds that
// wait for a request (docs/ADAPTIVE.md §1a, §3). Internal to the room.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "core/surface/surface_tree.h"

namespace tessera::surface_tree_building {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Nodes whose pair bound through the stand-in is below this many chain floors (10⁻⁵ of the
// diagonal) keep their direct bound: finer than any tile at the tolerances asked for, they are
// many (the deep levels of every EV chain) and the diagonal maps' bound is the costly one (§3b).
constexpr double kDiagonalFloor = 100;
// How many levels below a node its leaves are bounded against its diagonal map; farther down,
// the node kDiagonalReach + 1 levels below stands for them (pair_tightening.cpp).
constexpr int kDiagonalReach = 5;
// How many levels below a node its descendants are gathered for its flat pair bound (§3d); deeper
// ones stand in with their corners and pair bounds.
constexpr int kFlatReach = 3;

// Rounds a bound up to the next float, so that storing it in single precision keeps it a bound.
inline float roundUp(double value) {
  float f = float(value);
  return double(f) < value ? std::nextafter(f, kInfinity) : f;
}

// docs/ADAPTIVE.md §3: a square's pair fields at equal parameters through its stand-in g (within
// r of the surface; an exact piece is its own, r = 0) and its exact corner values: with B their
// bilinear interpolant, any triangle of the square with its vertices on its sides is within
// r + ‖g − B‖ + |twist|/4 + σ, σ the largest bow of a side carrying a vertex other than its
// corners; and the own bounds (no twist) its ancestors' direct bounds start from.
struct StandInPair {
  NodePair fields;
  double own;
  std::array<double, 4> ownBows;
};
StandInPair standInPair(const BezierNet& g, const Vec3d corners[4], double r);

// What the quadtree of a root is built from: regular patches and ring sectors, each a square.
struct Item {
  int level;
  uint64_t ix, iy;
  bool sector;
  uint32_t index;  // regular patch, or ring
  int ringSector;
};

// Where an EV quadrant sits in its ring: the ring, its sector and the FAS level.
struct ChainStep {
  uint32_t ring;
  int sector, level;
};

// A node's stand-in and the exact surface values at its corners, passed up while building.
struct NodeFit {
  BezierNet g;
  double r = 0;
  Vec3d corners[4];
};

class TreeBuilder {
 public:
  TreeBuilder(const PatchSet& patches, const ControlMesh& mesh, const std::function<void()>& checkpoint)
      : patches_(patches), mesh_(mesh), checkpoint_(checkpoint) {}
  SurfaceTree build(double chainFloor);

 private:
  void makeRoots();
  void refineRings();
  std::vector<std::vector<Item>> collectItems() const;
  uint32_t allocateChildren();
  void fill(uint32_t slot, int level, uint64_t ix, uint64_t iy, std::vector<Item>& items);
  void fillChain(uint32_t slot, uint32_t ring, int sector, int chainLevel);
  NodeFit summarize(uint32_t node, int level);
  NodeFit summarizeLeaf(SurfaceNode& node, int level) const;
  NodeFit ringStandIn(const ChainStep& step, int level) const;
  NodeFit fitChildren(const NodeFit children[4]) const;
  void setBox(uint32_t node, const ChainStep* step);
  void setStandIn(SurfaceNode& node, const NodeFit& fit, int level) const;
  void keepOwn(uint32_t index, const StandInPair& pair);
  void deferPairs(uint32_t index);
  BezierNet leafNet(const SurfaceNode& node) const;

  void checkpointNow() const {
    if (checkpoint_) checkpoint_();
  }

  const PatchSet& patches_;
  const ControlMesh& mesh_;
  const std::function<void()>& checkpoint_;
  SurfaceTree tree_;
  std::vector<ChainStep> chainSteps_;  // EV quadrants being built: node index → step
  std::vector<int32_t> chainOf_;

  double floor_ = 0;       // kChainFloor of the diagonal: the bounds' thresholds scale with it
  double chainFloor_ = 0;  // where the EV chains stop, in model units
  // Per ring and level refineRings reached: what every sector's EV quadrant shares and costs
  // O(ring size) to compute, so computed once (a valence-n ring has n sectors): the stand-in
  // bound, the EV's limit point (relative to the ring's centre) and the ring's box.
  struct RingLevel {
    double bound;
    Vec3d limit;
    float boxMin[3], boxMax[3];
  };
  std::vector<std::vector<RingLevel>> ringLevels_;
  RingLevel ringLevel(size_t r, const float* ring, int level) const;
};

}  // namespace tessera::surface_tree_building
