// The pair bound of one exact bicubic piece through a graded diagonal map (docs/ADAPTIVE.md §3c):
// §3b's twist-free bound for the two triangles through the piece's corners, with the map's grid
// lines placed so that its staircase follows where the surface comes nearest the pair's diagonal,
// so that a few cells follow a twisted parameterization that crowds toward one side (pieces beside
// semi-sharp creases).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "core/math/bezier_net.h"

namespace tessera {

struct PairBounds {
  double pair = 0;                  // sup ‖f ∘ φ − L‖ for the pair (no side points but corners)
  std::array<double, 4> bows{};     // what points on side k can add (docs/ADAPTIVE.md §3)
  uint8_t diagonal = 0;             // 1 + d: holds only split along diagonal d (SurfaceNode::pairDiagonal)
};

// The bicubic over the unit square with this net, against the pair through its corners along the
// better diagonal (the one nearer the surface at the map's grid points); none when that diagonal's
// gap at the grid points (a lower bound of the result) is not below `below`, or when the bound is
// found to be above `abortAbove` (its computation then stops there).
std::optional<PairBounds> gradedPairBounds(const BezierNet& net, double below, double abortAbove = INFINITY);

// A lower bound of every pair bound of the net, at equal parameters or through any map: the distance
// of f(½, ½) from the nearer of the pair's planes, for the diagonal that makes it smaller.
double pairLowerBound(const BezierNet& net);
// The same from the surface's corners and its value at the centre (a square of several pieces).
double pairLowerBound(const Vec3d corners[4], const Vec3d& centre);

}  // namespace tessera
