// Tiles that hold an extraordinary vertex (docs/ADAPTIVE.md §4): the curvature outside the open
// corner cells, the corner cells' stand-in terms, and the grid whose bound they allow.
#include <algorithm>

#include "core/adaptive/planner.h"

namespace tessera::adaptive_planning {

// The part of descendant `n` of an EV tile outside the tile's open corner cells: its curvature
// bound, walking down only the nodes that hold an EV (the others' bounds are finite).
Curvature Planner::outsideCorners(const NodeSquare& n, const NodeSquare& tile, int ru, int rv) const {
  const SurfaceNode& tileNode = tree_.nodes[tile.node];
  for (int c = 0; c < 4; ++c) {
    if ((tileNode.evCorners >> c & 1) && insideCornerCell(n, tile, c, ru, rv)) return {};
  }
  const SurfaceNode& node = tree_.nodes[n.node];
  if (node.evCorners == 0) return node.bound();
  if (node.isLeaf()) return {kInfinity, kInfinity, kInfinity};
  Curvature m;
  for (int q = 0; q < 4; ++q) m = m.max(outsideCorners(n.child(tree_, q), tile, ru, rv));
  return m;
}

// docs/ADAPTIVE.md §4: triangles that miss every open corner cell [0, w) × [0, h) at an EV
// corner lie where the curvature is bounded; a triangle that meets one lies in the doubled
// cell [0, 2w] × [0, 2h], inside the smallest EV node N'' holding that, whose stand-in g gives
// ‖f − L‖ ≤ 2 r + (w² M_uu(g) + 2 w h M_uv(g) + h² M_vv(g)) / 8.
double Planner::evTileBound(const NodeSquare& n, int ru, int rv) const {
  const double w = n.size() / ru, h = n.size() / rv;
  const SurfaceNode& node = tree_.nodes[n.node];
  // Every triangle lies in the tile itself, so its own stand-in always bounds it.
  const double standIn = 2.0 * node.standInBound + interpolationBound(node.standInCurvatureBound(), w, h);
  const Curvature outside = outsideCorners(n, n, ru, rv);
  double bound = outside.finite() ? interpolationBound(outside, w, h) : kInfinity;
  for (int c = 0; c < 4 && bound < standIn; ++c) {
    if (!(node.evCorners >> c & 1)) continue;
    NodeSquare holder = n;
    // The child at depth d holds the doubled cell when 2^-d >= 2/ru and 2/rv.
    for (int depth = 1; ru >= (1 << (depth + 1)) && rv >= (1 << (depth + 1)); ++depth) {
      if (tree_.nodes[holder.node].isLeaf()) break;
      const NodeSquare child = holder.child(tree_, quadrantOfCorner(c));
      if (!(tree_.nodes[child.node].evCorners >> c & 1)) break;
      holder = child;
    }
    const SurfaceNode& at = tree_.nodes[holder.node];
    bound = std::max(bound, 2.0 * at.standInBound + interpolationBound(at.standInCurvatureBound(), w, h));
  }
  return std::min(bound, standIn);
}

// Rates for a tile holding EVs from the curvature outside the corner cells (which grows as the
// cells shrink, so iterate to a fixed point) and the corner terms; doubling the rates moves the
// corner cells into deeper EV nodes with tighter stand-ins.
Rates Planner::evGridFor(const NodeSquare& n, double epsilon, int minRate) const {
  int ru = minRate, rv = minRate;
  for (int step = 0; step < 24; ++step) {
    const Curvature outside = outsideCorners(n, n, ru, rv);
    if (outside.finite()) {
      const Rates r = ratesFor(outside, n.size(), epsilon, minRate);
      if (!r.feasible()) return {};
      if (r.ru <= ru && r.rv <= rv) break;
      ru = std::max(ru, r.ru), rv = std::max(rv, r.rv);
    } else {
      ru *= 2, rv *= 2;
    }
    if (ru > kMaxTileRate || rv > kMaxTileRate) return {};
  }
  for (int attempt = 0; attempt < 3 && ru <= kMaxTileRate && rv <= kMaxTileRate; ++attempt) {
    const double bound = evTileBound(n, ru, rv);
    if (bound <= epsilon) return {ru, rv, bound};
    ru *= 2, rv *= 2;
  }
  return {};
}

}  // namespace tessera::adaptive_planning
