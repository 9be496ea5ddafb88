#include "core/adaptive/adaptive_plan.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/adaptive/grid_rates.h"
#include "core/adaptive/piece_pair_bounds.h"
#include "core/adaptive/planner.h"
#include "core/adaptive/tile_neighbors.h"
#include "core/adaptive/tile_rectangles.h"
#include "core/base/parallel_chunks.h"

namespace tessera {

namespace adaptive_planning {

void Planner::fillReal(const NodeSquare& n, Candidate& c) const {
  const SurfaceNode& node = tree_.nodes[n.node];
  c.real = n;
  c.level = n.level, c.ix = n.ix, c.iy = n.iy;
  c.m = node.evCorners ? Curvature{kInfinity, kInfinity, kInfinity} : node.bound();
  c.standIn = node.standInBound;
  c.gm = node.standInCurvatureBound();
  const PairTightening& tightening = tree_.tightening;
  const bool tightens = tightening.deferred(n.node) != PairTightening::Deferred::kNone;
  // An internal node's direct bounds wait for a request (direct_pair_bounds.cpp); a leaf's are its own.
  c.pairStage = !node.isLeaf()                     ? Candidate::PairStage::kStandIn
                : tightens                          ? Candidate::PairStage::kDirect
                                                    : Candidate::PairStage::kTight;
  // A leaf's own pair fields wait for the first plan that reads the leaf (directPairOf).
  setPair(c, node.isLeaf() ? directPairOf(tree_, patches_, n.node) : node.pairFields());
  c.onePiece = node.kind == NodeKind::kRegularLeaf || node.kind == NodeKind::kFasLeaf;
  c.edgesKnown = false;
  std::copy(node.boxMin, node.boxMin + 3, c.lo);
  std::copy(node.boxMax, node.boxMax + 3, c.hi);
}

void Planner::setPair(Candidate& c, const NodePair& pair) {
  c.pair = pair.pair;
  std::copy(pair.bows, pair.bows + 4, c.bows);
  c.diagonal = pair.diagonal;
}

Planner::Candidate Planner::realCandidate(const NodeSquare& n) const {
  Candidate c;
  fillReal(n, c);
  return c;
}

void Planner::fillQuadrant(const Candidate& parent, int q, Candidate& c) const {
  c.real = parent.real;
  c.level = parent.level + 1;
  c.ix = 2 * parent.ix + uint64_t(q & 1), c.iy = 2 * parent.iy + uint64_t(q >> 1);
  c.below = true;
  c.m = netCurvature(c.net.data()).scaled(exp2i(2 * c.level));
  c.standIn = 0;
  c.gm = c.m;
  c.pairKnown = false;
  c.pairStage = Candidate::PairStage::kTight;  // its pair is its own (pairKnown), not the leaf's
  c.onePiece = true;
  c.edgesKnown = false;
  // The box serves only a camera's depth (epsilonOf).
  if (!tolerance_.pixelAccurate()) return;
  for (int a = 0; a < 3; ++a) {
    double lo = c.net[0][a], hi = lo;
    for (const Vec3d& p : c.net) lo = std::min(lo, p[a]), hi = std::max(hi, p[a]);
    c.lo[a] = std::nextafter(float(lo), -INFINITY), c.hi[a] = std::nextafter(float(hi), INFINITY);
  }
}

Planner::Candidate Planner::quadrantCandidate(const Candidate& parent, const BezierNet& net, int q) const {
  Candidate c;
  c.net = net;
  fillQuadrant(parent, q, c);
  return c;
}

bool Planner::splittable(const Candidate& c) const {
  const SurfaceNode& node = tree_.nodes[c.real.node];
  if (node.kind == NodeKind::kEvBottom) return false;
  if (!node.isLeaf() && !c.below) return true;
  return c.level < kMaxTileLevel && c.level - c.real.level < kMaxSplitBelowLeaf;
}

void Planner::split(const Candidate& c, Candidate children[4]) const {
  const SurfaceNode& node = tree_.nodes[c.real.node];
  if (!c.below && !node.isLeaf()) {
    for (int q = 0; q < 4; ++q) fillReal(c.real.child(tree_, q), children[q]);
    return;
  }
  BezierNet* const nets[4] = {&children[0].net, &children[1].net, &children[2].net, &children[3].net};
  quadrantNets(c.below ? c.net : pieceNet(tree_, patches_, c.real.node), nets);
  for (int q = 0; q < 4; ++q) fillQuadrant(c, q, children[q]);
}

// The fewest triangles any of the bounds allows (docs/ADAPTIVE.md §2-4): the triangle pair
// through the corners, the curvature bound, the stand-in (2r + its curvature bound), and
// around EVs the corner cells.
// A root corner where the face meets one other face along both of its edges there (a valence-2
// vertex): a one-cell tile would join the two edges by a triangle the other face repeats back to
// back, so tiles there keep an inner grid point.
bool Planner::touchesPinchedCorner(const Candidate& c) const {
  const uint8_t pinched = rootPinched_;
  if (pinched == 0) return false;
  const uint64_t last = (uint64_t(1) << c.level) - 1;
  const bool at[4] = {c.ix == 0 && c.iy == 0, c.ix == last && c.iy == 0, c.ix == last && c.iy == last,
                      c.ix == 0 && c.iy == last};
  for (int k = 0; k < 4; ++k) {
    if ((pinched >> k & 1) && at[k]) return true;
  }
  return false;
}

void Planner::nextPairStage(Candidate& c, double epsilon) const {
  const uint32_t node = c.real.node;
  if (c.pairStage == Candidate::PairStage::kStandIn) {
    setPair(c, directPairOf(tree_, patches_, node));
    const bool tightens = tree_.tightening.deferred(node) != PairTightening::Deferred::kNone;
    c.pairStage = tightens ? Candidate::PairStage::kDirect : Candidate::PairStage::kTight;
    return;
  }
  // Tightened only as far as it takes to know whether it is within ε (pairWithin).
  const std::optional<NodePair> tight = pairWithin(tree_, patches_, node, epsilon);
  if (tight) {
    setPair(c, *tight);
  } else {
    c.pair = kInfinity;
  }
  c.pairStage = Candidate::PairStage::kTight;
}

// Whether the (1, 1) grid's pair bound can be within ε. A node's pair is computed stage by stage
// (Candidate::pairStage) only while the stage so far does not serve with its bows and the node's
// lower bound, which no stage goes below, leaves room; below a leaf it is computed only when the
// gap at the centre (a lower bound of it) leaves room, and the side bows only when it is. Every
// stage is a bound, so whichever serves first, the tile's bound holds; and a stage's values do not
// depend on what earlier requests computed, so neither does the plan.
bool Planner::pairMayServe(Candidate& c, double epsilon) const {
  while (c.pairStage != Candidate::PairStage::kTight) {
    // A triangular face's sub-faces, whole, may be joined into one triangle by their bounds'
    // size (core/stitching/face_triangles.h): theirs is the tightest.
    if (c.pairWithBows() <= epsilon && !(rootInTriangle_ && c.level == 0)) return true;
    if (c.pair > epsilon && !tree_.tightening.mayReach(c.real.node, epsilon)) return false;
    nextPairStage(c, epsilon);
  }
  if (!c.pairKnown) {
    if (centreGap(c.net) > epsilon) return false;
    c.pair = exactPairBound(c.net);
    if (c.pair > epsilon) return false;
    exactSideBows(c.net, c.bows);
    c.pairKnown = true;
  }
  return c.pair <= epsilon;
}

// docs/ADAPTIVE.md §2a on a square inside one piece: starting from §2's rates, the fewest cells
// §2's form allows for ε scaled by how much tighter §2a is at the rates so far (the two forms
// scale alike with the cells), kept only where §2a's bound holds.
Rates Planner::edgeGridFor(Candidate& c, const Rates& curvatureRates, double epsilon) const {
  if (!c.edgesKnown) {
    c.edges = c.below ? edgeCurvature(c.net) : edgeCurvatureOf(tree_, patches_, c.real.node);
    c.edgesKnown = true;
  }
  const EdgeCurvature& edges = c.edges;
  Rates best = curvatureRates, at = curvatureRates;
  for (int step = 0; step < 3; ++step) {
    const double tighter = gridTileBound(edges, at.ru, at.rv);
    if (tighter <= epsilon && at.triangles() < best.triangles()) best = {at.ru, at.rv, std::min(tighter, at.bound)};
    if (!(tighter < at.bound)) break;
    const Rates next = ratesFor(c.m, c.size(), epsilon * (at.bound / tighter), 2);
    if (!next.feasible() || (next.ru == at.ru && next.rv == at.rv)) break;
    at = next;
  }
  return best;
}

Rates Planner::gridFor(Candidate& c) const {
  const double epsilon = epsilonOf(c);
  const int minRate = touchesPinchedCorner(c) ? 2 : 1;
  if (minRate == 1 && pairMayServe(c, epsilon)) {
    if (c.pairWithBows() <= epsilon) return {1, 1, c.pairWithBows(), false, c.diagonal};
    // Whether the sides get points beside the corners is known only once the seams are stitched:
    // the pair alone, to be checked then (adaptive_tessellator.h).
    if (!conservative_) return pairOrSettledGrid(c, epsilon);
  }
  return settledGridFor(c, epsilon, minRate);
}

// The pair left pending, or the settled grid where the pair would save too little (kPendingSaving).
// A root's own square is left pending whatever it saves: its sides lie on base edges and spokes,
// across which the neighbours are whole roots too where ε is coarse, and those pass (bigguy at
// 1e-2 keeps one cell a face, 2,900 triangles, where the rule would make 3,138, in 4 % less time).
Rates Planner::pairOrSettledGrid(Candidate& c, double epsilon) const {
  const Rates settled = settledGridFor(c, epsilon, 1);
  if (c.level > 0 && settled.feasible() && settled.triangles() - 2 < kPendingSaving) return settled;
  Rates pair{1, 1, c.pair, true, c.diagonal};
  // Planning the square again would emit the settled grid without a split (plan()): a tile that
  // fails its check takes it in place.
  if (settled.feasible() && settled.triangles() - 8 < kSplitSaving) {
    pair.settledRu = uint8_t(settled.ru), pair.settledRv = uint8_t(settled.rv);
    pair.settledDiagonal = settled.diagonal, pair.settledBound = settled.bound;
  }
  return pair;
}

// The grid whose bound holds whatever points the sides get.
Rates Planner::settledGridFor(Candidate& c, double epsilon, int minRate) const {
  Rates best;
  auto consider = [&best](const Rates& r) {
    if (!r.feasible()) return;
    if (!best.feasible() || r.triangles() < best.triangles() ||
        (r.triangles() == best.triangles() && r.bound < best.bound)) {
      best = r;
    }
  };
  if (!c.below && tree_.nodes[c.real.node].evCorners) {
    consider(evGridFor(c.real, epsilon, minRate));
  } else {
    const Rates curvature = ratesFor(c.m, c.size(), epsilon, minRate);
    // §2a needs at least 2 × 2 cells: only a grid of more can get fewer.
    const bool tighter = c.onePiece && curvature.feasible() && curvature.ru * curvature.rv > 4;
    consider(tighter ? edgeGridFor(c, curvature, epsilon) : curvature);
  }
  if (c.standIn > 0 && epsilon > 2 * c.standIn) {
    Rates r = ratesFor(c.gm, c.size(), epsilon - 2 * c.standIn, minRate);
    if (r.feasible()) r.bound += 2 * c.standIn;
    consider(r);
  }
  return best;
}

void Planner::emit(const Candidate& c, const Rates& grid, std::vector<Tile>& out) const {
  Tile tile;
  tile.node = c.real;
  tile.level = c.level, tile.ix = c.ix, tile.iy = c.iy;
  tile.ru = grid.ru, tile.rv = grid.rv;
  tile.bound = float(grid.bound);
  tile.tolerance = float(epsilonOf(c));
  tile.diagonal = grid.diagonal;
  if (grid.optimistic) {
    tile.pendingPair = true;
    for (int k = 0; k < 4; ++k) tile.sideBow[k] = float(c.bows[k]);
    tile.settledRu = grid.settledRu, tile.settledRv = grid.settledRv;
    tile.settledDiagonal = grid.settledDiagonal, tile.settledBound = float(grid.settledBound);
  }
  out.push_back(tile);
}

// What emit() makes of the square of a pending tile with a settled grid, planned again.
Tile settledTile(const Tile& pending) {
  Tile tile;
  tile.node = pending.node;
  tile.level = pending.level, tile.ix = pending.ix, tile.iy = pending.iy;
  tile.ru = pending.settledRu, tile.rv = pending.settledRv;
  tile.bound = pending.settledBound;
  tile.tolerance = pending.tolerance;
  tile.diagonal = pending.settledDiagonal;
  return tile;
}

// A node becomes a tile unless its four quadrants, each tessellated on its own, need enough fewer
// triangles (one level of look-ahead, kSplitSaving); a node no grid can serve is always split.
// Quadrants make at least two triangles each, so a grid of fewer than kSplitSaving + 8 cannot
// be beaten and is emitted without looking ahead.
void Planner::plan(const Candidate& c, const Rates& grid, std::vector<Tile>& out) const {
  if (++sinceCheckpoint_ == kNodesPerCheckpoint) {
    sinceCheckpoint_ = 0;
    if (options_.checkpoint) options_.checkpoint();
  }
  if ((grid.feasible() && grid.triangles() - 8 < kSplitSaving) || !splittable(c)) {
    if (grid.feasible()) return emit(c, grid, out);
    // Nothing finer exists (the deepest EV quadrant below kChainFloor): the finest grid, its
    // bound reported as it is.
    const NodeSquare& n = c.real;
    const double bound = c.below || !tree_.nodes[n.node].evCorners
                             ? interpolationBound(c.m, c.size() / kMaxTileRate, c.size() / kMaxTileRate)
                             : evTileBound(n, kMaxTileRate, kMaxTileRate);
    return emit(c, {kMaxTileRate, kMaxTileRate, bound}, out);
  }
  Candidate children[4];
  split(c, children);
  Rates childGrids[4];
  int64_t childTriangles = 0;
  for (int q = 0; q < 4; ++q) {
    childGrids[q] = gridFor(children[q]);
    childTriangles += childGrids[q].feasible() ? childGrids[q].triangles() : std::numeric_limits<int32_t>::max();
    // The quadrants not planned yet make at least two triangles each: once even that leaves the
    // saving under kSplitSaving, the node is the tile (the rest are not planned).
    if (grid.feasible() && grid.triangles() - (childTriangles + 2 * (3 - q)) < kSplitSaving) return emit(c, grid, out);
  }
  const size_t first = out.size();
  for (int q = 0; q < 4; ++q) plan(children[q], childGrids[q], out);
  if (merging_) mergeCellwise(c, first, out);
}

// Four quadrants planned as one-cell tiles (or cell-wise tiles of one rate) become one cell-wise
// tile over the node: the same triangles, one tile's work. Sides between the quadrants get no
// points beside their own, so only the outer sides keep the pending quadrants' bows: the merged
// tile is pending if any quadrant was, with side k's bow the largest of the quadrants along it.
// Each cell keeps the diagonal its bound needs: cells that allow either take the one the others
// keep, and up to 4 × 4 cells, cells that keep different ones say so each (Tile::cellDiagonals).
void Planner::mergeCellwise(const Candidate& c, size_t first, std::vector<Tile>& out) const {
  if (out.size() != first + 4) return;
  const int rc = out[first].ru, r = 2 * rc;
  if (r > kMaxTileRate) return;
  uint8_t diagonal = 0;
  bool mixed = false;
  uint32_t cellDiagonals = 0;
  for (int q = 0; q < 4; ++q) {
    const Tile& t = out[first + size_t(q)];
    const bool cells = (t.ru == 1 && t.rv == 1) || t.cellwise;
    if (!cells || t.ru != rc || t.rv != rc || t.level != c.level + 1) return;
    for (int j = 0; j < rc; ++j) {
      for (int i = 0; i < rc; ++i) {
        const uint8_t d = t.cellDiagonal(i, j);
        mixed = mixed || (d != 0 && diagonal != 0 && d != diagonal);
        if (diagonal == 0) diagonal = d;
        const int at = (q & 1) * rc + i + r * ((q >> 1) * rc + j);
        if (r <= 4) cellDiagonals |= uint32_t(d) << (2 * at);
      }
    }
  }
  if (mixed && r > 4) return;
  Tile merged;
  merged.node = c.real;
  merged.level = c.level, merged.ix = c.ix, merged.iy = c.iy;
  merged.ru = merged.rv = r;
  merged.cellwise = true;
  merged.diagonal = mixed ? 0 : diagonal;
  merged.cellDiagonals = mixed ? cellDiagonals : 0;
  const Tile& head = out[first];
  merged.bound = 0, merged.tolerance = head.tolerance;
  for (size_t i = first; i < out.size(); ++i) {
    const Tile& t = out[i];
    merged.bound = std::max(merged.bound, t.bound);
    merged.tolerance = std::min(merged.tolerance, t.tolerance);
    if (!t.pendingPair) continue;
    merged.pendingPair = true;
    const bool right = t.ix & 1, top = t.iy & 1;
    const bool outer[4] = {!top, right, top, !right};
    for (int k = 0; k < 4; ++k) {
      if (outer[k]) merged.sideBow[k] = std::max(merged.sideBow[k], t.sideBow[k]);
    }
  }
  out.resize(first);
  out.push_back(merged);
}

void Planner::beginRoot(uint32_t root) const {
  const SurfaceRoot& r = tree_.roots[root];
  const SeamTopology& seams = patches_.adaptive->seams;
  rootPinched_ = 0;
  rootInTriangle_ = seams.faceSizes[r.baseFace] == 3;
  if (r.subFace < 0) {
    for (int k = 0; k < 4; ++k) rootPinched_ |= uint8_t(seams.pinched(r.baseFace, k) << k);
  } else {
    rootPinched_ = uint8_t(seams.pinched(r.baseFace, r.subFace));
  }
}

void Planner::planRoot(uint32_t root, std::vector<Tile>& out, RootTileIndex* index) const {
  beginRoot(root);
  conservative_ = false, merging_ = true;
  Candidate top = realCandidate({tree_.roots[root].node, 0, 0, 0});
  plan(top, gridFor(top), out);
  mergeRectangles(tree_, top.real, out);
  settleInnerSides(root, out, index);
}

// A pending tile's side inside its root gets its points from the root's own tiles alone, which
// the first round of neighbour checks (adaptive_tessellator.h) would see as they are here: a tile
// failing on such a side is planned again here, on the core that planned the root, a round
// earlier and without the round's pass over every root; the rounds then decide the sides on base
// edges and spokes. (The rounds' outcome depends a little on the order in which squares are planned
// again, as a square planned again as a grid keeps fewer points on its sides than the cell-wise
// tile it replaces: docs/ADAPTIVE.md §3.)
void Planner::settleInnerSides(uint32_t root, std::vector<Tile>& tiles, RootTileIndex* keep) const {
  thread_local RootTileIndex scratch;
  RootTileIndex& index = keep ? *keep : scratch;
  thread_local std::vector<Tile> replaced;
  for (bool failed = true; failed;) {
    failed = false;
    index.index(tiles);
    replaced.clear();
    for (uint32_t t = 0; t < tiles.size(); ++t) {
      Tile& tile = tiles[t];
      uint8_t sides = 0;
      for (int k = 0; k < 4 && tile.pendingPair; ++k) {
        if (!tile.onRootSide(k) && index.innerSideGetsPoints(tiles, t, k)) sides |= uint8_t(1 << k);
      }
      tile.innerSidesWithPoints = sides;
      if (tile.pendingPair && tile.boundWithPoints(sides) > tile.tolerance) {
        planSquare(root, tile, sides, replaced);
        failed = true;
      } else {
        replaced.push_back(tile);
      }
    }
    if (!failed) return;
    mergeRectangles(tree_, {tree_.roots[root].node, 0, 0, 0}, replaced);
    tiles.swap(replaced);
  }
}

void Planner::planSquare(uint32_t root, const Tile& tile, uint8_t sides, std::vector<Tile>& out) const {
  beginRoot(root);
  // A merged tile fails on some quadrants' sides, most often: the others keep the shortcut.
  const bool unmerge = tile.cellwise && tile.pendingPair;
  if (!unmerge && tile.settledRu > 0) return out.push_back(settledTile(tile));
  conservative_ = !unmerge, merging_ = !unmerge;
  // The tile's node, then de Casteljau quadrants down to the tile when it lies below a leaf.
  Candidate c = realCandidate(tile.node);
  while (c.level < tile.level) {
    const int d = tile.level - c.level - 1;
    const int q = int((tile.ix >> d) & 1) | int(((tile.iy >> d) & 1) << 1);
    const BezierNet net = quadrantNet(c.below ? c.net : pieceNet(tree_, patches_, c.real.node), q & 1, q >> 1);
    c = quadrantCandidate(c, net, q);
  }
  if (!unmerge) return plan(c, gridFor(c), out);
  std::vector<Tile> parts;
  plan(c, gridFor(c), parts);
  for (const Tile& part : parts) {
    if (part.pendingPair && part.boundWithPoints(sidesOnSquare(part, tile, sides)) > part.tolerance) {
      planSquare(root, part, 0, out);
    } else {
      out.push_back(part);
    }
  }
}

// Which of `sides` (bit k: side k of tile `square`) tile `part`, inside it, lies on.
uint8_t sidesOnSquare(const Tile& part, const Tile& square, uint8_t sides) {
  const int d = part.level - square.level;
  return sidesTouched(part.ix - (square.ix << d), part.iy - (square.iy << d), d) & sides;
}

}  // namespace adaptive_planning

using adaptive_planning::kInfinity;
using adaptive_planning::Planner;

void planRoots(const SurfaceTree& tree, const PatchSet& patches, const TessellationOptions& options, RootTiles& tiles,
               std::vector<RootTileIndex>* indexes) {
  validateTessellationOptions(options);
  tiles.resize(tree.roots.size());
  if (indexes) indexes->resize(tree.roots.size());
  forOwnedParts(tree.roots.size(), 16, [&](size_t, size_t first, size_t last) {
    if (options.checkpoint) options.checkpoint();
    const Planner planner(tree, patches, options);  // one per part: it keeps the current root's state
    for (size_t r = first; r != last; ++r) {
      tiles[r].clear();
      if (tree.roots[r].node != kNoNode) {
        planner.planRoot(uint32_t(r), tiles[r], indexes ? &(*indexes)[r] : nullptr);
      } else if (indexes) {
        (*indexes)[r].index(tiles[r]);  // a hole: nothing (the index may hold an earlier call's)
      }
    }
  });
}

void replanSquares(const SurfaceTree& tree, const PatchSet& patches, const TessellationOptions& options,
                   const std::vector<TileSquare>& failed, RootTiles& tiles, std::vector<RootTileIndex>* indexes) {
  std::vector<std::pair<size_t, size_t>> roots;  // ranges of `failed` with one root
  for (size_t i = 0; i < failed.size();) {
    size_t j = i;
    while (j < failed.size() && failed[j].root == failed[i].root) ++j;
    roots.push_back({i, j});
    i = j;
  }
  // Chunks of 8 roots or more: a round that re-plans a few squares (the small creased shapes)
  // does it on one thread, where a parallel region would cost more than the work.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, roots.size(), chunkFor(roots.size(), 8, 16)), [&](const auto& range) {
    const Planner planner(tree, patches, options);
    std::vector<Tile> replaced;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const uint32_t r = failed[roots[i].first].root;
      replaced.clear();
      for (const Tile& tile : tiles[r]) {
        const auto redo = std::find_if(failed.begin() + roots[i].first, failed.begin() + roots[i].second,
                                       [&tile](const TileSquare& q) {
                                         return q.level == tile.level && q.ix == tile.ix && q.iy == tile.iy;
                                       });
        if (redo != failed.begin() + roots[i].second) {
          planner.planSquare(r, tile, redo->sidesWithPoints, replaced);
        } else {
          replaced.push_back(tile);
        }
      }
      // The squares planned again settle (their pending quadrants aside): they may merge, and
      // what they now put on sides inside the root is checked there.
      mergeRectangles(tree, {tree.roots[r].node, 0, 0, 0}, replaced);
      planner.settleInnerSides(r, replaced, indexes ? &(*indexes)[r] : nullptr);
      tiles[r].swap(replaced);
    }
  });
}

AdaptivePlan flattenPlan(const RootTiles& tiles) {
  AdaptivePlan plan;
  plan.rootFirstTile.reserve(tiles.size() + 1);
  size_t count = 0;
  for (const std::vector<Tile>& root : tiles) count += root.size();
  plan.tiles.reserve(count);
  plan.tolerance = kInfinity;
  for (const std::vector<Tile>& root : tiles) {
    plan.rootFirstTile.push_back(uint32_t(plan.tiles.size()));
    for (const Tile& t : root) {
      plan.guaranteedBound = std::max(plan.guaranteedBound, double(t.bound));
      plan.tolerance = std::min(plan.tolerance, double(t.tolerance));
      plan.gridTriangles += 2 * int64_t(t.ru) * t.rv;
    }
    plan.tiles.insert(plan.tiles.end(), root.begin(), root.end());
  }
  plan.rootFirstTile.push_back(uint32_t(plan.tiles.size()));
  return plan;
}

}  // namespace tessera
