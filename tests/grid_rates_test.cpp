// A grid's rates (core/adaptive/grid_rates.h) against the search they stand for: every ru × rv from the
// least rate to kMaxTileRate, the fewest cells whose interpolation bound holds ε, ties going to
// the squarer grid and then the fewer cells along u.
#include "core/adaptive/grid_rates.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>

#include "core/adaptive/adaptive_plan.h"

namespace tessera {
namespace {

Rates everyGrid(const Curvature& m, double size, double epsilon, int minRate) {
  Rates best;
  for (int ru = minRate; ru <= kMaxTileRate; ++ru) {
    for (int rv = minRate; rv <= kMaxTileRate; ++rv) {
      const double bound = interpolationBound(m, size / ru, size / rv);
      if (bound > epsilon) continue;
      const int64_t cells = int64_t(ru) * rv, bestCells = int64_t(best.ru) * best.rv;
      const bool better = !best.feasible() || cells < bestCells ||
                          (cells == bestCells && std::abs(ru - rv) < std::abs(best.ru - best.rv));
      if (better) best = {ru, rv, bound};
    }
  }
  return best;
}

std::string describe(const Curvature& m, double size, double epsilon, int minRate) {
  char text[160];
  std::snprintf(text, sizeof text, "M = (%.17g, %.17g, %.17g), size %.17g, eps %.17g, min rate %d", m.uu, m.uv,
                m.vv, size, epsilon, minRate);
  return text;
}

void expectSameGrid(const Curvature& m, double size, double epsilon, int minRate) {
  const Rates expected = everyGrid(m, size, epsilon, minRate);
  const Rates got = ratesFor(m, size, epsilon, minRate);
  SCOPED_TRACE(describe(m, size, epsilon, minRate));
  ASSERT_EQ(got.feasible(), expected.feasible());
  if (!expected.feasible()) return;
  EXPECT_EQ(got.ru, expected.ru);
  EXPECT_EQ(got.rv, expected.rv);
  EXPECT_EQ(got.bound, expected.bound);
}

// Curvatures spread over six decades, each term alone or together (a zero term leaves one
// direction free, where the fewest cells lie at the least rate).
TEST(GridRates, FewestCellsOfEveryGridOnRandomCurvatures) {
  std::mt19937_64 random(20261129);
  std::uniform_real_distribution<double> exponent(-3, 3), unit(0, 1);
  for (int trial = 0; trial < 20000; ++trial) {
    Curvature m{std::pow(10.0, exponent(random)), std::pow(10.0, exponent(random)), std::pow(10.0, exponent(random))};
    const int zero = int(unit(random) * 8);
    if (zero & 1) m.uu = 0;
    if (zero & 2) m.uv = 0;
    if (zero & 4) m.vv = 0;
    const double size = std::pow(2.0, -int(unit(random) * 6));
    const double epsilon = std::pow(10.0, exponent(random) - 2);
    expectSameGrid(m, size, epsilon, unit(random) < 0.8 ? 1 : 2);
    if (HasFatalFailure()) return;
  }
}

// Grids whose bound meets ε exactly (w, h the cells of a known grid), where rounding decides.
TEST(GridRates, FewestCellsWhereTheBoundMeetsEpsilonExactly) {
  for (int ru = 1; ru <= 12; ++ru) {
    for (int rv = 1; rv <= 12; ++rv) {
      for (const Curvature& m : {Curvature{1, 0, 1}, Curvature{3, 0.5, 1}, Curvature{0.2, 2, 5}, Curvature{7, 0, 0}}) {
        expectSameGrid(m, 1, interpolationBound(m, 1.0 / ru, 1.0 / rv), 1);
      }
    }
  }
}

TEST(GridRates, NoGridWhereEvenTheFinestBreaksEpsilon) {
  const Curvature m{1e6, 1e6, 1e6};
  EXPECT_FALSE(ratesFor(m, 1, 1e-6).feasible());
  EXPECT_FALSE(ratesFor({INFINITY, 0, 0}, 1, 1).feasible());
  EXPECT_FALSE(ratesFor({1, 1, 1}, 1, 0).feasible());
}

}  // namespace
}  // namespace tessera
