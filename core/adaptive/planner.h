// The planner of core/adaptive/adaptive_plan.h's cut (docs/ADAPTIVE.md §6): per root, candidates
// (tree nodes and de Casteljau quadrants below leaves) planned top-down into tiles by the fewest
// triangles any bound allows. Internal to the room: adaptive_plan.cpp plans and settles roots with
// it, ev_tile_bounds.cpp bounds the tiles that hold an extraordinary vertex (§4).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/adaptive/grid_rates.h"
#include "core/bounds/edge_curvature.h"
#include "core/math/dyadic.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/tolerance_model.h"

namespace tessera::adaptive_planning {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
// A node is split only when its quadrants need at least this many fewer triangles: a tile costs
// planning, stitching and triangulation set-up worth about four triangles (measured on bigguy at
// 1e-3: ~1.5 us a tile, ~0.4 us a triangle), and a split makes three more. Against the earlier
// rule (split when the quadrants need at most 85 % of the triangles), on the nine benchmark
// models at 1e-2..1e-4 this gives 0.8 % fewer triangles summed in 12 % less time.
inline constexpr int64_t kSplitSaving = 8;
// A one-cell tile is left pending (planned on the pair bound through its corners, to be checked
// once its neighbours are known) only where it would save at least this many triangles over the
// grid that holds whatever its sides get. Most pending tiles fail their check (bigguy at 1e-3:
// three in four) and are planned again, and a failure cost more than the triangles it could
// save: on the nine benchmark models at 1e-2..1e-4, against leaving every such tile pending, 7
// took bigguy at 1e-3 from 6.4 to 5.3 ms on one thread (t-rex at 1e-4 −10 %, monsterfrog at 1e-3
// −9 %) for 2.8 % more triangles summed; 2.7 % with roots' own squares excepted (pairOrSettledGrid,
// docs/ADAPTIVE.md §3).
inline constexpr int64_t kPendingSaving = 7;
// How far below a leaf piece de Casteljau may split it, and the deepest tile level at all
// (tile coordinates stay exact integers).
inline constexpr int kMaxSplitBelowLeaf = 16;
inline constexpr int kMaxTileLevel = 48;

// Corner c of a square: which side it lies on along u and along v.
inline int cornerU(int c) { return c == 1 || c == 2 ? 1 : 0; }
inline int cornerV(int c) { return c >= 2 ? 1 : 0; }

// Whether descendant square `n` of tile square `t` lies in the closed corner cell of t's corner
// c for ru × rv cells, in exact integer arithmetic.
inline bool insideCornerCell(const NodeSquare& n, const NodeSquare& t, int c, int ru, int rv) {
  const int d = n.level - t.level;
  const int64_t span = int64_t(1) << d;
  const int64_t a = int64_t(n.ix - (t.ix << d)), b = int64_t(n.iy - (t.iy << d));
  const bool inU = cornerU(c) == 0 ? (a + 1) * ru <= span : a * ru >= (ru - 1) * span;
  const bool inV = cornerV(c) == 0 ? (b + 1) * rv <= span : b * rv >= (rv - 1) * span;
  return inU && inV;
}

uint8_t sidesOnSquare(const Tile& part, const Tile& square, uint8_t sides);

class Planner {
 public:
  Planner(const SurfaceTree& tree, const PatchSet& patches, const TessellationOptions& options)
      : tree_(tree), patches_(patches), options_(options), tolerance_(options, patches) {}
  void planRoot(uint32_t root, std::vector<Tile>& out, RootTileIndex* index) const;
  // The square of tile `tile` of `root` planned again with no optimistic one-cell tiles; a
  // pending cell-wise tile's square with its quadrants' tiles unmerged, those that the points on
  // `sides` (bit k: the square's side k got points) break planned again without the shortcut.
  void planSquare(uint32_t root, const Tile& tile, uint8_t sides, std::vector<Tile>& out) const;
  // The pending tiles of `root` that its own tiles already break (on sides inside the root)
  // planned again, until none does; `keep`, when given, is left indexing the tiles.
  void settleInnerSides(uint32_t root, std::vector<Tile>& tiles, RootTileIndex* keep) const;

 private:
  struct Candidate {
    NodeSquare real;
    int level = 0;
    uint64_t ix = 0, iy = 0;
    bool below = false;  // a de Casteljau quadrant below the leaf `real`
    BezierNet net;       // its net, when below
    Curvature m;          // exact curvature bound (infinite around an EV)
    double standIn = 0;    // r of the stand-in g, and g's curvature
    Curvature gm;
    double pair = 0;     // the (1, 1) grid's bound with no points on its sides but its corners
    double bows[4] = {0, 0, 0, 0};  // what points on each side add (docs/ADAPTIVE.md §3)
    uint8_t diagonal = 0;  // the diagonal pair and bows need (SurfaceNode::pairDiagonal)
    bool pairKnown = true;  // below a leaf, pair and bows are computed when a (1, 1) grid may do
    // How far the pair is computed: the build's fields (an internal node's stand-in), the direct
    // bounds over its pieces, the tightened ones (pair_tightening.h). Each stage is computed
    // only where the one before does not serve and the node's lower bound leaves room.
    enum class PairStage : uint8_t { kStandIn, kDirect, kTight } pairStage = PairStage::kTight;
    bool onePiece = false;  // the square lies in one bicubic piece (a leaf or below one)
    bool edgesKnown = false;  // `edges` is computed when a grid may use it
    EdgeCurvature edges;      // §2a's data of the net (a leaf's kept by the tree once computed)
    float lo[3], hi[3];
    double pairWithBows() const { return pair + *std::max_element(bows, bows + 4); }
    double size() const { return exp2i(-level); }
  };
  void fillReal(const NodeSquare& n, Candidate& c) const;
  static void setPair(Candidate& c, const NodePair& pair);
  Candidate realCandidate(const NodeSquare& n) const;
  // Quadrant q of `parent`, whose net `c.net` holds already (filled in place: a candidate is
  // ~600 bytes, and copying four per split was 4 % of a small request's instructions).
  void fillQuadrant(const Candidate& parent, int q, Candidate& c) const;
  Candidate quadrantCandidate(const Candidate& parent, const BezierNet& net, int q) const;
  bool splittable(const Candidate& c) const;
  void split(const Candidate& c, Candidate children[4]) const;
  Rates gridFor(Candidate& c) const;
  Rates settledGridFor(Candidate& c, double epsilon, int minRate) const;
  Rates pairOrSettledGrid(Candidate& c, double epsilon) const;
  bool pairMayServe(Candidate& c, double epsilon) const;
  void nextPairStage(Candidate& c, double epsilon) const;
  Rates edgeGridFor(Candidate& c, const Rates& curvatureRates, double epsilon) const;
  Rates evGridFor(const NodeSquare& n, double epsilon, int minRate) const;
  bool touchesPinchedCorner(const Candidate& c) const;
  double evTileBound(const NodeSquare& n, int ru, int rv) const;
  Curvature outsideCorners(const NodeSquare& n, const NodeSquare& tile, int ru, int rv) const;
  void plan(const Candidate& c, const Rates& grid, std::vector<Tile>& out) const;
  void emit(const Candidate& c, const Rates& grid, std::vector<Tile>& out) const;
  void mergeCellwise(const Candidate& c, size_t first, std::vector<Tile>& out) const;
  double epsilonOf(const Candidate& c) const { return tolerance_.forBox(c.lo, c.hi); }
  void beginRoot(uint32_t root) const;

  const SurfaceTree& tree_;
  const PatchSet& patches_;
  const TessellationOptions& options_;
  const ToleranceModel tolerance_;
  // The current root's pinched corners and whether it is a triangle's sub-face (beginRoot sets
  // them), whether optimistic one-cell tiles are off and whether quadrants are merged (planSquare).
  mutable uint8_t rootPinched_ = 0;
  mutable bool rootInTriangle_ = false;
  mutable bool conservative_ = false;
  mutable bool merging_ = true;
  // Nodes planned since the last checkpoint: one root at a fine tolerance is millions of nodes,
  // seconds of work that a cancelled request must not finish (the checkpoint every kNodesPerCheckpoint).
  mutable uint32_t sinceCheckpoint_ = 0;
  static constexpr uint32_t kNodesPerCheckpoint = 4096;
};

}  // namespace tessera::adaptive_planning
