// A grid tile's rates: the fewest cells ru × rv whose interpolation bound (docs/ADAPTIVE.md §2,
// FMM86 form) holds ε over a square, and the planner's record of the grid it chose (adaptive_plan.cpp).
#pragma once

#include <cstdint>
#include <limits>

#include "core/math/bezier_net.h"

namespace tessera {

// An infeasible grid has an infinite bound.
struct Rates {
  int ru = 1, rv = 1;
  double bound = std::numeric_limits<double>::infinity();
  bool optimistic = false;  // a (1, 1) pair whose sides must stay free of points beside the corners
  uint8_t diagonal = 0;     // a (1, 1) pair bound that holds along this diagonal only (Tile::diagonal)
  // An optimistic pair's settled grid, when planning the square again would emit it (Tile::settledRu).
  uint8_t settledRu = 0, settledRv = 0, settledDiagonal = 0;
  double settledBound = 0;
  bool feasible() const { return bound < std::numeric_limits<double>::infinity(); }
  int64_t triangles() const { return 2 * int64_t(ru) * rv; }
};

// The fewest cells ru · rv with (w² M_uu + 2 w h M_uv + h² M_vv) / 8 ≤ ε for w = s/ru, h = s/rv,
// each at least minRate and at most kMaxTileRate (infeasible where none is).
Rates ratesFor(const Curvature& m, double size, double epsilon, int minRate = 1);

}  // namespace tessera
