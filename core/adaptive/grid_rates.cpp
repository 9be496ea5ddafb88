#include "core/adaptive/grid_rates.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>

#include "core/adaptive/adaptive_plan.h"

namespace tessera {

namespace {

// 1/r for every rate, rounded once (constant evaluation rounds as the hardware does).
constexpr std::array<double, kMaxTileRate + 2> kInverse = [] {
  std::array<double, kMaxTileRate + 2> inverse{};
  for (int r = 1; r <= kMaxTileRate + 1; ++r) inverse[size_t(r)] = 1.0 / r;
  return inverse;
}();

bool powerOfTwo(double x) {
  const uint64_t bits = std::bit_cast<uint64_t>(x);
  const uint64_t exponent = bits >> 52 & 0x7ff;
  return (bits & ((uint64_t(1) << 52) - 1)) == 0 && exponent > 0 && exponent < 0x7ff;
}

// §2's bound over a square of size s with ru × rv cells is Q(ru, rv) / 8 for
// Q = a / ru² + 2 b / (ru rv) + c / rv² (a = s² M_uu, b = s² M_uv, c = s² M_vv), against
// target = 8ε. The bound itself (interpolationBound) decides; the real solutions only say where
// to look and where to stop, with a hair of slack for their rounding.
class RateSearch {
 public:
  RateSearch(const Curvature& m, double size, double epsilon, int minRate)
      : m_(m), size_(size), epsilon_(epsilon), minRate_(minRate), exactCells_(powerOfTwo(size)),
        a_(m.uu * size * size), b_(m.uv * size * size), c_(m.vv * size * size), target_(8 * epsilon) {}

  // The real optimum of ru · rv on Q = target: there c / rv² = a / ru², so
  // ru* = √((2a + 2b √(a/c)) / target) (Lagrange on 1/ru, 1/rv). Without a v term, the least ru
  // the u term allows; without a u term, the least rate.
  int start() const {
    double ru = minRate_;
    if (a_ > 0 && c_ > 0) ru = std::sqrt((2 * a_ + 2 * b_ * std::sqrt(a_ / c_)) / target_);
    if (a_ > 0 && c_ == 0) ru = std::floor(std::sqrt(a_ / target_)) + 1;
    return int(std::clamp(ru, double(minRate_), double(kMaxTileRate)) + 0.5);
  }

  // Whether no ru' past ru (away from ru*) can have `cells` or fewer: ru's real rv already gives
  // more. ru · rv_real(ru) is unimodal in ru (x y on the ellipse Q(1/x, 1/y) = target is
  // log-concave in x), so once it exceeds `cells` moving away from its minimum it stays above;
  // moving towards it, it stays under the cells of the grids already seen, and this never holds.
  bool beyond(int ru, int64_t cells, double inverseCells) const {
    if (cells < int64_t(ru) * minRate_) return true;
    const double q = a_ * square(kInverse[ru]) + 2 * b_ * inverseCells + c_ * double(ru) * ru * square(inverseCells);
    return q > target_ * (1 + 1e-9);
  }

  // Whether the u term alone breaks ε at ru (and so at every smaller ru).
  bool uTermBreaks(int ru) const { return a_ * square(kInverse[ru]) > target_ * (1 + 1e-9); }

  // The least rv with ru whose bound holds ε (0 where none up to kMaxTileRate does): the real
  // root of Q(ru, rv) = target in 1/rv, k / (p + √(p² + c k)) with k = target − a/ru² and
  // p = b/ru (no cancellation), rounded up, then the bound's own test.
  int leastRv(int ru) const {
    const double k = target_ - a_ * square(kInverse[ru]), p = b_ * kInverse[ru];
    double rvReal = minRate_;
    if (k > 0) {
      rvReal = (p + std::sqrt(p * p + c_ * k)) / k;
    } else if (p > 0 || c_ > 0) {
      return 0;
    }
    int rv = std::max(minRate_, int(std::ceil(std::min(rvReal, double(kMaxTileRate + 1)) - 1e-9)));
    while (rv <= kMaxTileRate && !holds(ru, rv)) ++rv;
    return rv <= kMaxTileRate ? rv : 0;
  }

  // The least rv with ru + 1, from ru's least rv (the bound shrinks as cells narrow, so it holds).
  int leastRvAfter(int ru, int rv) const {
    while (rv > minRate_ && holds(ru + 1, rv - 1)) --rv;
    return rv;
  }

  bool holds(int ru, int rv) const { return bound(ru, rv) <= epsilon_; }
  double bound(int ru, int rv) const { return interpolationBound(m_, cell(ru), cell(rv)); }

 private:
  static double square(double x) { return x * x; }
  // s / r; for a power-of-two size (a node's square always) s · (1/r) is the same to the bit.
  double cell(int r) const { return exactCells_ ? size_ * kInverse[r] : size_ / r; }

  const Curvature& m_;
  double size_, epsilon_;
  int minRate_;
  bool exactCells_;
  double a_, b_, c_, target_;
};

}  // namespace

// The fewest cells ru · rv, ties to the squarer grid, then to the fewer cells along u: from the
// real optimum ru*, outwards in both directions until RateSearch::beyond. Against trying every ru
// from the least rate with a square root and four divisions each (the creased torus at 1e-3:
// 7.4 rates a call, 17 % of one thread's time), about three rates, most of them by
// multiplications alone.
Rates ratesFor(const Curvature& m, double size, double epsilon, int minRate) {
  Rates best;
  if (!m.finite() || !(epsilon > 0)) return best;
  const RateSearch search(m, size, epsilon, minRate);
  int64_t bestCells = std::numeric_limits<int64_t>::max();
  double inverseCells = 0;
  auto consider = [&](int ru, int rv) {
    if (rv == 0) return;
    const int64_t cells = int64_t(ru) * rv;
    const int skew = std::abs(ru - rv), bestSkew = std::abs(best.ru - best.rv);
    if (cells < bestCells || (cells == bestCells && (skew < bestSkew || (skew == bestSkew && ru < best.ru)))) {
      if (cells != bestCells) inverseCells = 1.0 / double(cells);
      bestCells = cells;
      best = {ru, rv, search.bound(ru, rv)};
    }
  };
  const int start = search.start();
  const int startRv = search.leastRv(start);
  consider(start, startRv);
  for (int ru = start + 1, rv = startRv; ru <= kMaxTileRate; ++ru) {
    if (best.feasible() && search.beyond(ru, bestCells, inverseCells)) break;
    rv = rv == 0 ? search.leastRv(ru) : search.leastRvAfter(ru - 1, rv);
    consider(ru, rv);
  }
  for (int ru = start - 1; ru >= minRate && !search.uTermBreaks(ru); --ru) {
    if (best.feasible() && search.beyond(ru, bestCells, inverseCells)) break;
    consider(ru, search.leastRv(ru));
  }
  return best;
}

}  // namespace tessera
