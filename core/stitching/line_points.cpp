#include "core/stitching/line_points.h"

#include <algorithm>
#include <numeric>

namespace tessera::line_points {

namespace {

Int remainder(Int a, Int b) { return fits64(a) && fits64(b) ? Int(int64_t(a) % int64_t(b)) : a % b; }

Int gcd(Int a, Int b) {
  if (a < 0) a = -a;
  while (b != 0) {
    const Int r = remainder(a, b);
    a = b, b = r;
  }
  return a;
}

// Use indices ordered by key, ties in index order. Lines hold a handful of uses: insertion sort,
// with no buffer to allocate as std::stable_sort has.
void stableSortUses(std::vector<uint32_t>& order, const std::vector<Int>& key) {
  for (size_t i = 1; i < order.size(); ++i) {
    const uint32_t moving = order[i];
    size_t j = i;
    for (; j > 0 && key[moving] < key[order[j - 1]]; --j) order[j] = order[j - 1];
    order[j] = moving;
  }
}

// One stretch of a line (resolveLine): its uses' ends and kept own points, then for each
// use, densest first, its own points wherever two neighbouring points are farther apart than its
// cell (so that no side sees a gap wider than its cells, tile_stitching.h). Appends the points
// after those already in out.points, the stretch's start (an end both share) once.
void resolveStretch(const LineUse* uses, const uint32_t* members, size_t count, LinePoints& out) {
  std::vector<Int>& points = out.stretch;
  points.clear();
  const uint32_t head = members[0];
  bool sameSpan = true;
  uint32_t densest = head;
  for (size_t m = 0; m < count; ++m) {
    const uint32_t i = members[m];
    sameSpan &= out.lo[i] == out.lo[head] && out.hi[i] == out.hi[head];
    if (out.cell[i] < out.cell[densest]) densest = i;
  }
  // A side's kept points are among the densest side's when their intervals divide its cells.
  for (size_t m = 0; m < count && sameSpan; ++m) sameSpan = uses[densest].cells % uses[members[m]].kept == 0;
  if (sameSpan) {
    // Sides over one stretch (the common seam, or a boundary of the surface): the densest one's
    // points, which is what the rule comes to.
    for (int k = 0; k <= uses[densest].cells; ++k) points.push_back(out.lo[head] + k * out.cell[densest]);
  } else {
    for (size_t m = 0; m < count; ++m) {
      const uint32_t i = members[m];
      points.push_back(out.lo[i]);
      points.push_back(out.hi[i]);
      const int every = uses[i].cells / uses[i].kept;
      for (int k = every; k < uses[i].cells; k += every) points.push_back(out.lo[i] + k * out.cell[i]);
    }
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    std::vector<uint32_t>& order = out.order;
    order.assign(members, members + count);
    stableSortUses(order, out.cell);
    std::vector<Int>& merged = out.merged;
    for (uint32_t i : order) {
      const Int lo = out.lo[i], hi = out.hi[i], cell = out.cell[i];
      const auto first = std::lower_bound(points.begin(), points.end(), lo);
      auto p = first;
      while (p + 1 != points.end() && *(p + 1) <= hi && *(p + 1) - *p <= cell) ++p;
      if (p + 1 == points.end() || *(p + 1) > hi) continue;  // no gap wider than its cell
      // The points so far with its own points in every wide gap, still in order.
      merged.assign(points.begin(), first);
      for (p = first; p + 1 != points.end() && *(p + 1) <= hi; ++p) {
        merged.push_back(*p);
        if (*(p + 1) - *p <= cell) continue;
        for (Int own = lo + (quotient(*p - lo, cell) + 1) * cell; own < *(p + 1); own += cell) merged.push_back(own);
      }
      merged.insert(merged.end(), p, points.end());
      points.swap(merged);
    }
  }
  const bool shared = !out.points.empty() && out.points.back() == points.front();
  out.points.insert(out.points.end(), points.begin() + (shared ? 1 : 0), points.end());
}

// Whether every use is the same side span with the same cells: most lines inside a root, two
// tiles of one size and rate facing each other.
bool alike(const LineUse* uses, size_t count) {
  if (count == 0) return false;
  for (size_t i = 1; i < count; ++i) {
    if (uses[i].a != uses[0].a || uses[i].sign != uses[0].sign || uses[i].cells != uses[0].cells ||
        uses[i].exp != uses[0].exp) {
      return false;
    }
  }
  return true;
}

// resolveLine for alike uses, what its general rule comes to there: the denominator is the cells
// times 2^exp, every cell 1, and the points are the shared side's own.
void resolveAlike(const LineUse* uses, size_t count, LinePoints& out) {
  const LineUse& use = uses[0];
  out.denominator = Int(use.cells) << use.exp;
  const Int p0 = use.a, p1 = use.a + use.sign * use.cells;
  out.lo.assign(count, std::min(p0, p1));
  out.hi.assign(count, std::max(p0, p1));
  out.cell.assign(count, 1);
  out.points.clear();
  for (int k = 0; k <= use.cells; ++k) out.points.push_back(out.lo[0] + k);
}

}  // namespace

// A line's points, in units of 1/denominator (the least common multiple of its sides' cells).
// Its uses fall into stretches that no use crosses, and a point added inside a use's span depends
// only on the uses over that span, so each stretch is resolved on its own (resolveStretch): the
// two pairs of sides on the line between four tiles are two common seams.
void resolveLine(const LineUse* uses, size_t count, LinePoints& out) {
  if (alike(uses, count)) return resolveAlike(uses, count, out);
  Int rates = 1;
  int exp = 0;
  for (size_t i = 0; i < count; ++i) {
    rates = quotient(rates, gcd(rates, uses[i].cells)) * uses[i].cells;
    exp = std::max(exp, uses[i].exp);
  }
  out.denominator = rates << exp;
  out.lo.resize(count), out.hi.resize(count), out.cell.resize(count);
  for (size_t i = 0; i < count; ++i) {
    const LineUse& use = uses[i];
    out.cell[i] = quotient(out.denominator, Int(use.cells) << use.exp);
    const Int p0 = use.a * out.cell[i], p1 = (use.a + use.sign * use.cells) * out.cell[i];
    out.lo[i] = std::min(p0, p1), out.hi[i] = std::max(p0, p1);
  }
  std::vector<uint32_t>& byLo = out.byLo;
  byLo.resize(count);
  std::iota(byLo.begin(), byLo.end(), 0u);
  stableSortUses(byLo, out.lo);
  out.points.clear();
  for (size_t s = 0; s < count;) {
    Int end = out.hi[byLo[s]];
    size_t e = s + 1;
    while (e < count && out.lo[byLo[e]] < end) end = std::max(end, out.hi[byLo[e++]]);
    resolveStretch(uses, byLo.data() + s, e - s, out);
    s = e;
  }
}

// The uses of a line in order of where they start (ties in their given order): walked along with
// the sorted points, the first use holding each point is found in one pass.
const std::vector<uint32_t>& byStart(LinePoints& points) {
  std::vector<uint32_t>& order = points.order;
  order.resize(points.lo.size());
  std::iota(order.begin(), order.end(), 0u);
  stableSortUses(order, points.lo);
  return order;
}

}  // namespace tessera::line_points
