#include "core/grid_rates.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/adaptive_plan.h"

namespace tessera {

// The fewest cells ru · rv with (w² M_uu + 2 w h M_uv + h² M_vv) / 8 ≤ ε for w = s/ru, h = s/rv
// (docs/ADAPTIVE.md §2): for each ru the smallest rv solves a quadratic in 1/rv.
Rates ratesFor(const Curvature& m, double size, double epsilon, int minRate) {
  Rates best;
  if (!m.finite() || !(epsilon > 0)) return best;
  const double a = m.uu * size * size, b = m.uv * size * size, c = m.vv * size * size;
  const double target = 8 * epsilon;
  // However many cells along u, rv ≥ √(c / 8ε) (the h² M_vv term alone): past the ru where even
  // that gives more cells than the best so far, nothing better follows (the floor lowered by a
  // hair so that rounding in the bound never skips a tie).
  const double rvFloor = std::max(double(minRate), std::sqrt(c / target) * (1 - 1e-9));
  int64_t bestCells = std::numeric_limits<int64_t>::max();
  for (int ru = minRate; ru <= kMaxTileRate && ru < bestCells && double(ru) * rvFloor <= double(bestCells); ++ru) {
    const double k = target - a / (double(ru) * ru);
    if (k <= 0) continue;
    double rvReal = 1;
    if (c > 0) {
      const double y = (-b / ru + std::sqrt(b * b / (double(ru) * ru) + c * k)) / c;
      rvReal = 1 / y;
    } else if (b > 0) {
      rvReal = 2 * b / (k * ru);
    }
    int rv = std::max(minRate, int(std::ceil(std::min(rvReal, double(kMaxTileRate + 1)) - 1e-9)));
    while (rv <= kMaxTileRate && interpolationBound(m, size / ru, size / rv) > epsilon) ++rv;
    if (rv > kMaxTileRate) continue;
    const int64_t cells = int64_t(ru) * rv;
    if (cells < bestCells || (cells == bestCells && std::abs(ru - rv) < std::abs(best.ru - best.rv))) {
      bestCells = cells;
      best = {ru, rv, interpolationBound(m, size / ru, size / rv)};
    }
  }
  return best;
}

}  // namespace tessera
