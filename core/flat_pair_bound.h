// The pair bound of a nearly flat piece (docs/ADAPTIVE.md §3d): a geometric bound by projection
// onto one plane, which needs no map between the piece's parameters and the pair's. Pieces beside
// semi-sharp creases are slivers whose parameterization no map of §3b or §3c follows, while the
// surface lies within a small fraction of ε of one plane.
#pragma once

#include <optional>

#include "core/bezier_net.h"
#include "core/graded_pair_bound.h"

namespace tessera {

struct FlatPairBound {
  // Two-sided distance between the piece and the pair through its corners (either diagonal).
  double pair = 0;
  // The same for any triangulation whose vertices are the corners and points of the piece's sides.
  double anyTriangulation = 0;
};

// The bicubic piece with this net against its pair, projected along the normal n of the pair's
// diagonals: none when the corners' projection is not a strictly convex quad (§3d's claim needs it).
std::optional<FlatPairBound> flatPairBound(const BezierNet& net);

// Takes the flat bound where its pair is below `bounds.pair`, with the bows and diagonal
// (SurfaceNode::pairDiagonal) that then hold; false where it keeps `bounds`.
bool keepFlatBound(const BezierNet& net, PairBounds& bounds);

}  // namespace tessera
